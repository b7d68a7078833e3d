// A sample's de-lit albedo splatted into the neutral face's texture frame through its landmark fit.
#include "libs/fit/albedo_unwrap.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/util/error.h"
#include "core/util/math_constants.h"
#include "libs/fit/fit_prior.h"
#include "libs/fit/fit_render.h"
#include "libs/fit/fit_shading.h"
#include "libs/image/gaussian_blur.h"

namespace facetool {
namespace {

// The planes of `names` in order, each checked to exist.
std::vector<float> planes(const LayeredImage& sample, const std::string& source, const std::vector<std::string>& names) {
  const size_t plane = sample.plane_size();
  std::vector<float> out(names.size() * plane);
  for (size_t k = 0; k < names.size(); ++k) {
    const int c = sample.find_channel(names[k]);
    check(c >= 0, "sample '", source, "' has no ", names[k],
          " channel: unwrap needs fit-labelled samples (`facetool pseudo-label --from fit`) or synthetic ones");
    std::copy(sample.plane(c), sample.plane(c) + plane, out.begin() + static_cast<std::ptrdiff_t>(k * plane));
  }
  return out;
}

}  // namespace

AlbedoTexture unwrap_albedo(const LayeredImage& sample, const std::string& source, const FitBasis& basis,
                            const FitSettings& fit_settings, const AlbedoTextureFrame& frame,
                            const UnwrapSettings& settings) {
  check(frame.size >= 8 && frame.span > 0, "unwrap: the texture frame is empty");
  const LandmarkTarget target = read_sample_landmarks(sample, source);
  const std::vector<float> image = planes(sample, source, {"R", "G", "B"});
  const std::vector<float> sample_mask = planes(sample, source, {"mask"});
  const std::vector<float> normal = planes(sample, source, {"normal.X", "normal.Y", "normal.Z"});
  std::vector<std::string> visibility_names;
  for (int j = 0; j < 9; ++j) visibility_names.push_back("visibility." + std::to_string(j));
  const std::vector<float> visibility = planes(sample, source, visibility_names);
  const std::string* light_text = sample.find_metadata("facetool:light_sh");
  check(light_text != nullptr, "sample '", source, "' has no facetool:light_sh (the light its labels were made with)");
  std::istringstream light_in(*light_text);
  double light[27];
  for (double& l : light) light_in >> l;
  check(!light_in.fail(), "sample '", source, "': facetool:light_sh must hold 27 numbers");

  const FaceFit fit = fit_landmarks(basis, target, fit_settings);
  FitRenderSettings render;
  render.visibility = false;
  const FitRendering rendering = render_fit(basis.model(), fit, nullptr, render);
  const size_t plane = sample.plane_size();
  std::vector<uint8_t> used(plane, 0);
  for (size_t p = 0; p < plane; ++p)
    used[p] = sample_mask[p] > 0.5f && rendering.head[p] && rendering.mask[p] &&
              rendering.normal[2 * plane + p] >= settings.min_facing;
  const std::vector<double> transfer = transfer_coefficients(normal, visibility, used, plane);

  const int n = frame.size;
  const size_t texels = static_cast<size_t>(n) * n;
  std::vector<float> sums(4 * texels, 0.0f);  // planar: weighted R, G, B, then the weights
  for (size_t p = 0; p < plane; ++p) {
    if (!used[p]) continue;
    float albedo[3];
    bool lit = true;
    for (int c = 0; c < 3; ++c) {
      double shading = 0;
      for (int i = 0; i < 9; ++i) shading += light[c * 9 + i] * transfer[i * plane + p];
      shading /= kPi;
      lit = lit && shading >= settings.min_shading;
      albedo[c] = lit ? std::clamp(static_cast<float>(image[c * plane + p] / shading), 0.0f, settings.max_albedo) : 0.0f;
    }
    if (!lit) continue;
    float u, v;
    albedo_texel(frame, rendering.reference[p], false, u, v);
    const int x0 = static_cast<int>(std::floor(u)), y0 = static_cast<int>(std::floor(v));
    const float fx = u - static_cast<float>(x0), fy = v - static_cast<float>(y0);
    const float facing = rendering.normal[2 * plane + p];
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const int x = x0 + dx, y = y0 + dy;
        if (x < 0 || y < 0 || x >= n || y >= n) continue;
        const float w = facing * (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy);
        const size_t t = static_cast<size_t>(y) * n + x;
        for (int c = 0; c < 3; ++c) sums[c * texels + t] += w * albedo[c];
        sums[3 * texels + t] += w;
      }
  }
  sums = gaussian_blur(sums, 4, n, n, settings.spread_texels);

  AlbedoTexture texture;
  texture.frame = frame;
  texture.source = source;
  texture.rgb.assign(3 * texels, 0.0f);
  texture.weight.assign(texels, 0.0f);
  // Weights relative to a well-seen texel's: half the 90th percentile of the non-zero ones.
  std::vector<float> seen;
  for (size_t t = 0; t < texels; ++t)
    if (sums[3 * texels + t] > 0) seen.push_back(sums[3 * texels + t]);
  if (seen.empty()) return texture;
  std::nth_element(seen.begin(), seen.begin() + static_cast<std::ptrdiff_t>(0.9 * (seen.size() - 1)), seen.end());
  const float full = 0.5f * seen[static_cast<size_t>(0.9 * (seen.size() - 1))];
  for (size_t t = 0; t < texels; ++t) {
    const float w = sums[3 * texels + t];
    if (w <= 1e-6f * full) continue;
    for (int c = 0; c < 3; ++c) texture.rgb[c * texels + t] = sums[c * texels + t] / w;
    texture.weight[t] = std::min(1.0f, w / full);
  }
  return texture;
}

}  // namespace facetool
