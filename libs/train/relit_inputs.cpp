// Training augmentation: labelled photos relit by a random one-sided light (ratio relighting).
#include "libs/train/relit_inputs.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/sh/pixel_transfer.h"
#include "core/sh/sh_basis.h"
#include "core/sh/sh_eval.h"
#include "core/util/error.h"
#include "core/util/math_constants.h"
#include "libs/relight/relight_math.h"
#include "libs/train/grey_inputs.h"

namespace facetool {
namespace {

// Seeds the relit rows' draws apart from the grey rows' (any constant other than 0 does).
constexpr uint64_t kRelightSalt = 0x5265'6C69'6768'7421ull;

double unit_interval(uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

// The share of labelled pixels among the image's pixels within kRelightFeather of each pixel:
// 1 inside the region, falling to about a half at its edge.
std::vector<float> feather(const std::vector<uint8_t>& labelled, int64_t w, int64_t h) {
  const int64_t r = kRelightFeather;
  std::vector<float> out(labelled.size(), 0.0f);
  for (int64_t y = 0; y < h; ++y)
    for (int64_t x = 0; x < w; ++x) {
      int inside = 0, all = 0;
      for (int64_t v = std::max<int64_t>(0, y - r); v <= std::min(h - 1, y + r); ++v)
        for (int64_t u = std::max<int64_t>(0, x - r); u <= std::min(w - 1, x + r); ++u) {
          inside += labelled[v * w + u];
          ++all;
        }
      out[y * w + x] = static_cast<float>(inside) / static_cast<float>(all);
    }
  return out;
}

}  // namespace

bool relit_row(uint64_t seed, int64_t step, int source, int64_t row, double fraction) {
  return row_drawn(seed ^ kRelightSalt, step, source, row, fraction);
}

sh::RgbLight one_sided_light(const sh::Vec3& direction, double ambient) {
  // A distant light of power P projects to P Y_i(d); a uniform radiance R to 2 sqrt(pi) R on
  // Y_0 and gives a facing surface pi R of irradiance, so R = ambient / pi.
  sh::ShCoeffs c = sh::sh_basis(direction);
  c[0] += 2.0 * std::sqrt(kPi) * ambient / kPi;
  sh::RgbLight light{};
  for (int ch = 0; ch < 3; ++ch) sh::set_light_channel(light, ch, c);
  return light;
}

RelightDraw relight_draw(uint64_t seed, int64_t step, int source, int64_t row, RelightLight kind) {
  const uint64_t h0 = row_hash(seed ^ kRelightSalt ^ 1, step, source, row);
  const uint64_t h1 = row_hash(seed ^ kRelightSalt ^ 2, step, source, row);
  const uint64_t h2 = row_hash(seed ^ kRelightSalt ^ 3, step, source, row);
  const bool hard = kind == RelightLight::kHard;
  const double max_azimuth = hard ? 90.0 : 75.0;
  const double min_elevation = hard ? -30.0 : -10.0, max_elevation = hard ? 65.0 : 40.0;
  const double azimuth = (-max_azimuth + 2 * max_azimuth * unit_interval(h0)) * kPi / 180.0;
  const double elevation = (min_elevation + (max_elevation - min_elevation) * unit_interval(h1)) * kPi / 180.0;
  RelightDraw d;
  d.direction = {std::sin(azimuth) * std::cos(elevation), std::sin(elevation),
                 std::cos(azimuth) * std::cos(elevation)};
  d.ambient = hard ? 0.02 + 0.28 * unit_interval(h2) : 0.05 + 0.35 * unit_interval(h2);
  return d;
}

double hard_direct_shading(const sh::Vec3& n, const sh::ShCoeffs& visibility, const sh::Vec3& direction) {
  const double cosine = n[0] * direction[0] + n[1] * direction[1] + n[2] * direction[2];
  if (cosine <= 0) return 0.0;
  return cosine * std::clamp(sh::sh_eval(visibility, direction), 0.0, 1.0) / kPi;
}

void relight_some_rows(SyntheticBatch& batch, uint64_t seed, int64_t step, int source, double fraction,
                       int64_t first_row, RelightLight kind) {
  if (fraction <= 0) return;
  const Shape& s = batch.image.shape();
  check(s.rank() == 4 && s.c() == 3, "relit inputs: expected an image [N, 3, H, W], got ", s.str());
  const int64_t n_rows = s.n();
  std::vector<int64_t> rows;
  for (int64_t n = 0; n < n_rows; ++n)
    if (relit_row(seed, step, source, first_row + n, fraction)) rows.push_back(n);
  if (rows.empty()) return;
  const size_t plane = static_cast<size_t>(s.h()) * s.w();
  std::vector<float> image = batch.image.to_host(), light = batch.light.to_host();
  const bool hard = kind == RelightLight::kHard;
  std::vector<float> input = hard ? image : std::vector<float>();
  const std::vector<float> normal = batch.normal.to_host(), visibility = batch.visibility.to_host();
  const std::vector<float> mask = batch.mask.to_host();
  bool changed = false;
  for (const int64_t n : rows) {
    float* old_light = light.data() + n * sh::kLightCoeffCount;
    if (std::all_of(old_light, old_light + sh::kLightCoeffCount, [](float v) { return v == 0.0f; })) continue;
    const std::vector<float> nrm(normal.begin() + n * 3 * plane, normal.begin() + (n + 1) * 3 * plane);
    const std::vector<float> vis(visibility.begin() + n * 9 * plane, visibility.begin() + (n + 1) * 9 * plane);
    std::vector<uint8_t> labelled(plane);
    size_t count = 0;
    for (size_t p = 0; p < plane; ++p) {
      const double len2 = double(nrm[p]) * nrm[p] + double(nrm[plane + p]) * nrm[plane + p] +
                          double(nrm[2 * plane + p]) * nrm[2 * plane + p];
      labelled[p] = len2 > 0.25 && mask[n * plane + p] > 0.5f;
      count += labelled[p];
    }
    if (count == 0) continue;
    const std::vector<double> t = transfer_coefficients(nrm, vis, labelled, plane);
    const RelightDraw draw = relight_draw(seed, step, source, first_row + n, kind);
    sh::RgbLight fresh = one_sided_light(draw.direction, draw.ambient);
    // The hard light's shading before its scale: its exact direct part and the ambient's SH part
    // (a uniform radiance is exact in the 9 coefficients).
    std::vector<double> hard_shading;
    if (hard) {
      hard_shading.assign(plane, 0.0);
      const double ambient_l0 = 2.0 * std::sqrt(kPi) * draw.ambient / kPi;
      for (size_t p = 0; p < plane; ++p) {
        if (!labelled[p]) continue;
        sh::ShCoeffs v;
        for (int i = 0; i < sh::kCoeffCount; ++i) v[i] = vis[i * plane + p];
        hard_shading[p] = hard_direct_shading({nrm[p], nrm[plane + p], nrm[2 * plane + p]}, v, draw.direction) +
                          ambient_l0 * t[p] / kPi;
      }
    }
    // Per channel: the old and new shading, the new light scaled to the old mean (the SH one's
    // scale serves the hard one too: both are the same light).
    std::vector<float> old_shading(3 * plane), new_shading(3 * plane), hard_new(hard ? 3 * plane : 0);
    for (int c = 0; c < 3; ++c) {
      double old_sum = 0, new_sum = 0;
      for (size_t p = 0; p < plane; ++p) {
        if (!labelled[p]) continue;
        double o = 0, f = 0;
        for (int i = 0; i < sh::kCoeffCount; ++i) {
          o += old_light[c * sh::kCoeffCount + i] * t[i * plane + p];
          f += fresh[c * sh::kCoeffCount + i] * t[i * plane + p];
        }
        old_shading[c * plane + p] = static_cast<float>(o / kPi);
        new_shading[c * plane + p] = static_cast<float>(f / kPi);
        old_sum += o;
        new_sum += std::max(f, 0.0);
      }
      const double k = new_sum > 0 && old_sum > 0 ? old_sum / new_sum : 0.0;
      for (int i = 0; i < sh::kCoeffCount; ++i) fresh[c * sh::kCoeffCount + i] *= k;
      for (size_t p = 0; p < plane; ++p) {
        new_shading[c * plane + p] = static_cast<float>(new_shading[c * plane + p] * k);
        if (hard) hard_new[c * plane + p] = static_cast<float>(hard_shading[p] * k);
      }
    }
    const std::vector<float> weight = feather(labelled, s.w(), s.h());
    auto relight_row = [&](float* img, const std::vector<float>& shading) {
      for (int c = 0; c < 3; ++c)
        for (size_t p = 0; p < plane; ++p) {
          if (!labelled[p]) continue;
          const float gain = relight::ratio_factor(shading[c * plane + p], old_shading[c * plane + p],
                                                   relight::kDefaultRatioEpsilon);
          img[c * plane + p] *= 1.0f + weight[p] * (std::min(gain, kMaxRelightGain) - 1.0f);
        }
    };
    relight_row(image.data() + n * 3 * plane, new_shading);
    if (hard) relight_row(input.data() + n * 3 * plane, hard_new);
    for (int i = 0; i < sh::kLightCoeffCount; ++i) old_light[i] = static_cast<float>(fresh[i]);
    changed = true;
  }
  if (!changed) return;
  batch.image = Tensor::from_host(batch.image.backend(), s, image);
  if (hard) batch.input_image = Tensor::from_host(batch.image.backend(), s, input);
  batch.light = Tensor::from_host(batch.light.backend(), batch.light.shape(), light);
}

}  // namespace facetool
