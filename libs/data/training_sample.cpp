// Reading synthetic and real (possibly pseudo-labelled) sample files into TrainingSample planes.
#include "libs/data/training_sample.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "libs/io/exr_io.h"
#include "libs/synth/synth_sample.h"
#include "core/plugin/network_plugin.h"
#include "core/util/error.h"

namespace facetool {
namespace {

const char kPrefix[] = "facetool:";

void copy_channels(const LayeredImage& image, const std::vector<std::string>& names,
                   const std::string& path, std::vector<float>& out) {
  const size_t plane = image.plane_size();
  out.resize(names.size() * plane);
  for (size_t k = 0; k < names.size(); ++k) {
    const float* p = image.plane(image.require_channel(names[k], path));
    std::copy(p, p + plane, out.begin() + k * plane);
  }
}

TrainingSample read_real(const LayeredImage& image, const std::string& path, bool need_labels) {
  TrainingSample s;
  s.real = true;
  s.width = image.width;
  s.height = image.height;
  copy_channels(image, {"R", "G", "B"}, path, s.image);
  copy_channels(image, {"mask"}, path, s.mask);
  const size_t plane = image.plane_size();
  const std::string* light = image.find_metadata(std::string(kPrefix) + "light_sh");
  s.labelled = image.find_channel("albedo.R") >= 0 && light != nullptr;
  if (!s.labelled) {
    check(!need_labels, "real sample '", path, "' has no labels (albedo, normal, visibility ",
          "channels and facetool:light_sh) but its source is trained with supervised terms; run ",
          "`facetool pseudo-label --model STAGE1.safetensors ", path, " -o DIR` first, or use ",
          "kind \"real\" with only the term recon_albedo_normal_light");
    s.albedo.assign(3 * plane, 0.0f);
    s.normal.assign(3 * plane, 0.0f);
    s.visibility.assign(9 * plane, 0.0f);
    s.light.assign(27, 0.0f);
    return s;
  }
  copy_channels(image, {"albedo.R", "albedo.G", "albedo.B"}, path, s.albedo);
  copy_channels(image, {"normal.X", "normal.Y", "normal.Z"}, path, s.normal);
  std::vector<std::string> vis;
  for (int j = 0; j < 9; ++j) vis.push_back("visibility." + std::to_string(j));
  copy_channels(image, vis, path, s.visibility);
  std::istringstream in(*light);
  double v;
  while (in >> v) s.light.push_back(static_cast<float>(v));
  check(s.light.size() == 27 && in.eof(), "real sample '", path,
        "': facetool:light_sh must hold 27 numbers");
  return s;
}

// Refuses a NaN or infinite value of `values` (planes of width x height) naming the sample, the
// part, the plane and the pixel: it would otherwise surface steps later as a divergence or a
// renderer error far from its cause.
void check_finite(const std::vector<float>& values, const std::string& part, int width,
                  int height, const std::string& path) {
  const size_t w = static_cast<size_t>(std::max(1, width));
  const size_t plane = w * static_cast<size_t>(std::max(1, height));
  for (size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i])) {
      const size_t p = i % plane;
      fail("sample '", path, "' holds a NaN or infinite ", part, " value (channel ", i / plane,
           ", pixel (", p % w, ", ", p / w, ")); regenerate or remove the file");
    }
}

TrainingSample checked(TrainingSample s, const std::string& path) {
  check_finite(s.image, "image", s.width, s.height, path);
  check_finite(s.mask, "mask", s.width, s.height, path);
  check_finite(s.albedo, "albedo", s.width, s.height, path);
  check_finite(s.normal, "normal", s.width, s.height, path);
  check_finite(s.visibility, "visibility", s.width, s.height, path);
  check_finite(s.prior, "input prior", s.width, s.height, path);
  for (size_t k = 0; k < s.light.size(); ++k)
    check(std::isfinite(s.light[k]), "sample '", path, "' holds a NaN or infinite light ",
          "coefficient (number ", k, "); regenerate or remove the file");
  return s;
}

TrainingSample read_synthetic(const LayeredImage& image, const std::string& path) {
  const SynthSample synth = synth_sample_from_image(image, path);
  TrainingSample s;
  s.width = synth.width;
  s.height = synth.height;
  s.image = synth.image;
  s.albedo = synth.albedo;
  s.normal = synth.normal;
  s.mask = synth.mask;
  s.visibility = synth.visibility;
  for (double v : synth.light) s.light.push_back(static_cast<float>(v));
  s.labelled = true;
  return s;
}

// The input prior's channels (input_prior_channels: only "fit_normal" has any).
void read_prior(const LayeredImage& image, const std::string& path, const std::string& input_prior,
                std::vector<float>& out) {
  check(input_prior_channels(input_prior) == 3, "unknown input prior '", input_prior, "'");
  const std::vector<std::string> names{"prior.X", "prior.Y", "prior.Z"};
  for (const std::string& name : names)
    check(image.find_channel(name) >= 0, "sample '", path, "' has no ", name, " channel but the network takes ",
          "the fit's normals as input (network.input_prior \"", input_prior, "\"); add them with ",
          "`facetool pseudo-label --from fit` (--prior-only keeps the sample's labels)");
  // The same fit as the network's (its field of view): another one is another input.
  const std::string* made = image.find_metadata("facetool:input_prior");
  if (made)
    check(*made == input_prior, "sample '", path, "' carries the input prior '", *made,
          "' but the network takes '", input_prior, "'; make its prior again with `facetool pseudo-label --from fit ",
          "--prior-only` and the network's field of view (--fov)");
  copy_channels(image, names, path, out);
}

}  // namespace

std::vector<double> sample_landmarks(const LayeredImage& image, const std::string& path) {
  std::vector<double> points;
  const std::string* text = image.find_metadata(std::string(kPrefix) + "landmarks");
  if (!text) return points;
  std::istringstream in(*text);
  double v;
  while (in >> v) points.push_back(v);
  check(points.size() == 136 && in.eof(), "sample '", path, "': facetool:landmarks must hold 136 numbers ",
        "(68 points); regenerate the sample");
  for (double c : points)
    check(std::isfinite(c), "sample '", path, "' holds a NaN or infinite landmark coordinate; regenerate the sample");
  return points;
}

TrainingSample read_training_sample(const std::string& path, bool need_labels, const std::string& input_prior) {
  const LayeredImage image = read_exr(path, kPrefix);
  const std::string* version = image.find_metadata(std::string(kPrefix) + "generator_version");
  TrainingSample s = version && *version == kRealSampleVersion ? read_real(image, path, need_labels)
                                                                : read_synthetic(image, path);
  if (!input_prior.empty()) read_prior(image, path, input_prior, s.prior);
  const std::vector<double> points = sample_landmarks(image, path);
  s.landmarks.assign(points.begin(), points.end());
  return checked(std::move(s), path);
}

std::vector<float> read_training_sample_landmarks(const std::string& path) {
  const std::vector<double> points = sample_landmarks(read_exr_header(path, kPrefix), path);
  return std::vector<float>(points.begin(), points.end());
}

void read_training_sample_size(const std::string& path, int& width, int& height) {
  const LayeredImage header = read_exr_header(path, kPrefix);
  width = header.width;
  height = header.height;
}

std::string read_training_sample_framing(const std::string& path) {
  const LayeredImage header = read_exr_header(path, kPrefix);
  const std::string* framing = header.find_metadata("facetool:framing");
  return framing ? *framing : "v1";
}

}  // namespace facetool
