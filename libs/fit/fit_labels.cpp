// Fitting a real sample's crop landmarks, rendering at the crop's size, solving light and albedo.
#include "libs/fit/fit_labels.h"

#include <cstdio>
#include <map>

#include "libs/fit/fit_prior.h"
#include "libs/fit/normal_smoothing.h"
#include "libs/synth/gbuffer.h"
#include "core/util/error.h"

namespace facetool {

LayeredImage fit_labelled_sample(const LayeredImage& sample, const std::string& source, const FitBasis& basis,
                                 const PhotoFitOptions& options, const VisibilitySampler& sampler,
                                 const std::string& label, LabelMask mask_kind) {
  const LandmarkTarget target = read_sample_landmarks(sample, source);
  const int r = sample.find_channel("R"), g = sample.find_channel("G"), b = sample.find_channel("B");
  check(r >= 0 && g >= 0 && b >= 0, "sample '", source, "' has no R, G, B channels");
  const FaceFit fit = fit_landmarks(basis, target, options.fit);
  FitRenderSettings render = options.render;
  render.visibility = true;
  render.normal_smoothing = 0;  // the input prior below takes the mesh's own normals, as at run time
  FitRendering rendering = render_fit(basis.model(), fit, &sampler, render);
  const std::vector<float> mesh_normals = rendering.normal;
  smooth_normals(rendering.normal, rendering.head, sample.width, sample.height,
                 options.render.normal_smoothing * fitted_eye_distance_px(fit, rendering.mesh));
  const size_t plane = sample.plane_size();
  std::vector<float> image(3 * plane);
  for (int c = 0; c < 3; ++c) std::copy(sample.plane(c == 0 ? r : c == 1 ? g : b), sample.plane(c == 0 ? r : c == 1 ? g : b) + plane, image.begin() + c * plane);
  // Light and albedo from the pixels both masks trust: the fitted face region inside the
  // sample's own mask (the landmark hull), eroded by one pixel (edges mix background).
  std::vector<uint8_t> trusted(plane, 0);
  const int mask_channel = sample.find_channel("mask");
  for (size_t p = 0; p < plane; ++p)
    trusted[p] = rendering.mask[p] && (mask_channel < 0 || sample.plane(mask_channel)[p] > 0.5f);
  trusted = erode_mask(trusted, sample.width, sample.height);
  const ShadingSolve solve = solve_light_and_albedo(image, rendering.normal, rendering.visibility, trusted,
                                                    sample.width, sample.height);
  std::map<std::string, const float*> planes;
  std::vector<std::string> names;
  auto add = [&](const std::string& name, const float* data) {
    if (!planes.count(name)) names.push_back(name);
    planes[name] = data;
  };
  for (int c = 0; c < sample.channel_count(); ++c) add(sample.channel_names[c], sample.plane(c));
  // The mask the losses use: by default where every label holds, the trusted pixels. Beyond them
  // the albedo label is 0 (the solve has no pixels there) and the photo may be the fill outside
  // its edge; the whole fitted region (kFitted) puts about 40 % of its pixels there.
  std::vector<float> mask(plane);
  for (size_t p = 0; p < plane; ++p)
    mask[p] = (mask_kind == LabelMask::kTrusted ? trusted[p] : rendering.mask[p]) ? 1.0f : 0.0f;
  add("mask", mask.data());
  const char* albedo[3] = {"albedo.R", "albedo.G", "albedo.B"};
  const char* normal[3] = {"normal.X", "normal.Y", "normal.Z"};
  for (int c = 0; c < 3; ++c) {
    add(albedo[c], solve.albedo.data() + c * plane);
    add(normal[c], rendering.normal.data() + c * plane);
  }
  for (int j = 0; j < 9; ++j) add("visibility." + std::to_string(j), rendering.visibility.data() + j * plane);
  LayeredImage out(sample.width, sample.height, names);
  for (size_t k = 0; k < names.size(); ++k)
    std::copy(planes[names[k]], planes[names[k]] + plane, out.plane(static_cast<int>(k)));
  out.metadata = sample.metadata;
  std::string light;
  char buffer[40];
  for (int k = 0; k < 27; ++k) {
    std::snprintf(buffer, sizeof buffer, "%.9g", solve.light[k]);
    light += (k ? " " : "") + std::string(buffer);
  }
  out.set_metadata("facetool:light_sh", light);
  out.set_metadata("facetool:pseudo_labels", label);
  std::snprintf(buffer, sizeof buffer, "%.4g", fit.rms_px);
  out.set_metadata("facetool:fit_landmark_rms_px", buffer);
  // The mesh's own normals (unsmoothed, as fit_prior_normals gives them at run time) as the input
  // prior, when the fit's settings make one (input_prior_name).
  const std::string prior = input_prior_name(options.fit);
  return prior.empty() ? out : with_prior_channels(out, mesh_normals, 0.0, prior);
}

}  // namespace facetool
