// Reading a sample's crop landmarks, jittering them, and adding the fit's normals as prior channels.
#include "libs/fit/fit_prior.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/plugin/network_plugin.h"
#include "core/util/error.h"
#include "libs/data/training_sample.h"
#include "libs/fit/fit_render.h"
#include "libs/synth/random.h"

namespace facetool {

LandmarkTarget read_sample_landmarks(const LayeredImage& sample, const std::string& source) {
  const std::vector<double> points = sample_landmarks(sample, source);
  check(!points.empty(), "sample '", source, "' has no facetool:landmarks: the fit needs the samples of ",
        "`facetool prepare-real`, or of `facetool synth` from a face model (this version writes them)");
  LandmarkTarget target;
  target.width = sample.width;
  target.height = sample.height;
  for (int i = 0; i < kLandmarkCount; ++i) target.landmarks[i] = {points[2 * i], points[2 * i + 1]};
  return target;
}

Landmarks68 add_landmark_noise(const Landmarks68& landmarks, double sigma_px, uint64_t seed) {
  Random random(seed);
  Landmarks68 out = landmarks;
  for (Point2& p : out) {
    p.x += sigma_px * random.normal();
    p.y += sigma_px * random.normal();
  }
  return out;
}

Landmarks68 jitter_landmarks(const Landmarks68& landmarks, double fraction, uint64_t seed) {
  check(fraction >= 0 && std::isfinite(fraction), "landmark noise must be a fraction >= 0, got ", fraction);
  auto centre = [&](int first) {
    Point2 c{0, 0};
    for (int i = first; i < first + 6; ++i) c = {c.x + landmarks[i].x / 6, c.y + landmarks[i].y / 6};
    return c;
  };
  const Point2 a = centre(36), b = centre(42);
  return add_landmark_noise(landmarks, fraction * std::hypot(a.x - b.x, a.y - b.y), seed);
}

FitSettings prior_fit_settings(const std::string& input_prior) {
  check(input_prior_channels(input_prior) == 3, "input prior '", input_prior, "' is not the fit's normals");
  FitSettings settings;
  std::istringstream in(input_prior);
  std::string kind, fov;
  if (in >> kind >> fov) in >> settings.fov_deg;
  return settings;
}

std::string input_prior_name(const FitSettings& s) {
  const FitSettings d;
  const bool others_default =
      s.camera == d.camera && s.jaw == d.jaw && s.jaw_weight == d.jaw_weight && s.contour_rounds == d.contour_rounds &&
      s.identity_prior == d.identity_prior && s.expression_prior == d.expression_prior &&
      s.expression_smoothness == d.expression_smoothness && s.fit_expressions == d.fit_expressions &&
      s.robust_scale == d.robust_scale && s.max_iterations == d.max_iterations &&
      s.function_tolerance == d.function_tolerance;
  if (!others_default) return "";
  if (s.fov_deg == d.fov_deg) return "fit_normal";
  char name[48];
  std::snprintf(name, sizeof name, "fit_normal fov %.6g", s.fov_deg);
  return name;
}

LayeredImage with_prior_channels(const LayeredImage& sample, const std::vector<float>& normals,
                                 double landmark_noise, const std::string& input_prior) {
  const size_t plane = sample.plane_size();
  check(normals.size() == 3 * plane, "prior: expected ", 3 * plane, " normal values, got ", normals.size());
  const char* names[3] = {"prior.X", "prior.Y", "prior.Z"};
  std::vector<std::string> channels = sample.channel_names;
  for (const char* name : names)
    if (std::find(channels.begin(), channels.end(), name) == channels.end()) channels.push_back(name);
  LayeredImage out(sample.width, sample.height, channels);
  for (int c = 0; c < sample.channel_count(); ++c)
    std::copy(sample.plane(c), sample.plane(c) + plane, out.plane(out.find_channel(sample.channel_names[c])));
  for (int c = 0; c < 3; ++c)
    std::copy(normals.begin() + c * plane, normals.begin() + (c + 1) * plane, out.plane(out.find_channel(names[c])));
  out.metadata = sample.metadata;
  char noise[40];
  std::snprintf(noise, sizeof noise, "%.4g", landmark_noise);
  out.set_metadata("facetool:input_prior", input_prior);
  out.set_metadata("facetool:prior_landmark_noise", noise);
  return out;
}

std::vector<float> fit_prior_normals(const FitBasis& basis, const LandmarkTarget& target, const FitSettings& settings) {
  FitRenderSettings render;
  render.visibility = false;
  return render_fit(basis.model(), fit_landmarks(basis, target, settings), nullptr, render).normal;
}

LayeredImage fit_prior_sample(const LayeredImage& sample, const std::string& source, const FitBasis& basis,
                              const FitSettings& settings, double landmark_noise, uint64_t seed) {
  const std::string name = input_prior_name(settings);
  check(!name.empty(), "the fit's normals as an input prior take the fit's default settings but its field of view "
        "(--fov); other fit options would not be made again for a photo");
  LandmarkTarget target = read_sample_landmarks(sample, source);
  if (landmark_noise > 0) target.landmarks = jitter_landmarks(target.landmarks, landmark_noise, seed);
  return with_prior_channels(sample, fit_prior_normals(basis, target, settings), landmark_noise, name);
}

}  // namespace facetool
