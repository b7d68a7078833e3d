// Network weights: safetensors <-> network plugin parameters, with strict checks.
#include "libs/model/network_weights.h"

#include <cmath>
#include <set>

#include "core/util/error.h"
#include "libs/model/landmark_normals.h"

namespace facetool {
namespace {

std::vector<int64_t> dims_of(const Shape& s) {
  std::vector<int64_t> d;
  for (int i = 0; i < s.rank(); ++i) d.push_back(s[i]);
  return d;
}

int parse_positive_int(const std::string& text, const char* key, const std::string& path) {
  size_t used = 0;
  int value = 0;
  try {
    value = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  check(used == text.size() && value > 0, "weights file '", path, "': metadata '", key,
        "' must be a positive integer, got '", text, "'");
  return value;
}

void load_tensor(const SafeTensors& file, const std::string& path, const std::string& name,
                 const Tensor& target) {
  check(file.contains(name), "weights file '", path, "' lacks tensor '", name,
        "' (was it saved by another architecture or version?)");
  const SafeTensors::Entry& e = file.entry(name);
  check(e.dtype == "F32", "weights file '", path, "': tensor '", name, "' has dtype ", e.dtype,
        ", expected F32");
  const std::vector<int64_t> expected = dims_of(target.shape());
  if (e.shape != expected) {
    std::string got = "[";
    for (size_t i = 0; i < e.shape.size(); ++i) got += (i ? ", " : "") + std::to_string(e.shape[i]);
    fail("weights file '", path, "': tensor '", name, "' has shape ", got, "] but the network ",
         "needs ", target.shape().str());
  }
  const std::vector<float> values = file.floats(name);
  for (size_t k = 0; k < values.size(); ++k)
    check(std::isfinite(values[k]), "weights file '", path, "': tensor '", name, "' holds a ",
          std::isnan(values[k]) ? "NaN" : "infinite", " value at element ", k,
          " (a diverged or damaged training run: use an earlier checkpoint)");
  // A variance is never negative: batch norm would take the square root of a negative number
  // and every output would be NaN.
  const bool variance = name.size() >= 4 && name.compare(name.size() - 4, 4, "_var") == 0;
  for (size_t k = 0; variance && k < values.size(); ++k)
    check(values[k] >= 0.0f, "weights file '", path, "': tensor '", name, "' holds the ",
          "negative variance ", values[k], " at element ", k,
          " (a damaged file: use an earlier copy)");
  target.copy_from_host(values);
}

}  // namespace

WeightsHeader read_weights_header(const SafeTensors& file, const std::string& path) {
  const auto& meta = file.metadata();
  auto get = [&](const char* key) -> const std::string& {
    auto it = meta.find(key);
    check(it != meta.end(), "weights file '", path, "' has no '", key, "' metadata; it was not ",
          "written by facetool (see docs/model-format.md for the expected fields)");
    return it->second;
  };
  check(get("format") == kWeightsFormat, "weights file '", path, "' has format '", get("format"),
        "', expected '", kWeightsFormat, "'");
  const int version = parse_positive_int(get("format_version"), "format_version", path);
  check(version == kWeightsFormatVersion, "weights file '", path, "' has format version ", version,
        " but this facetool reads version ", kWeightsFormatVersion);
  // "linear_rgb", or "linear_rgb+PRIOR" for a network that also takes an input prior.
  const std::string& input = get("input");
  const std::string rgb = "linear_rgb";
  check(input.compare(0, rgb.size(), rgb) == 0 && (input.size() == rgb.size() || input[rgb.size()] == '+'),
        "weights file '", path, "' expects input convention '", input, "', this facetool feeds 'linear_rgb' ",
        "or 'linear_rgb+PRIOR'");
  WeightsHeader h;
  if (input.size() > rgb.size()) {
    h.config.input_prior = input.substr(rgb.size() + 1);
    try {
      input_prior_channels(h.config.input_prior);
    } catch (const Error& e) {
      throw Error("weights file '" + path + "': " + e.what() + " (written by a newer facetool?)");
    }
  }
  h.architecture = get("architecture");
  h.config.width = parse_positive_int(get("width"), "width", path);
  h.config.input_size = parse_positive_int(get("input_size"), "input_size", path);
  if (auto it = meta.find("framing"); it != meta.end())
    h.framing = parse_framing(it->second, "weights file '" + path + "': metadata 'framing'");
  return h;
}

void load_network_weights(NetworkPlugin& net, const SafeTensors& file, const std::string& path) {
  std::set<std::string> expected;
  for (const auto& [name, variable] : net.parameters()) {
    load_tensor(file, path, name, variable.value());
    expected.insert(name);
  }
  for (const auto& [name, tensor] : net.buffers()) {
    load_tensor(file, path, name, tensor);
    expected.insert(name);
  }
  for (const std::string& name : file.names())
    check(expected.count(name) != 0 || is_landmark_normals_tensor(name), "weights file '", path, "' holds tensor '", name,
          "' that this network does not have (another architecture?)");
}

void save_network_weights(const NetworkPlugin& net, const std::string& architecture,
                          const std::string& path, const CropFraming& framing) {
  SafeTensorsWriter writer;
  writer.set_metadata("format", kWeightsFormat);
  writer.set_metadata("format_version", std::to_string(kWeightsFormatVersion));
  writer.set_metadata("architecture", architecture);
  writer.set_metadata("width", std::to_string(net.config().width));
  writer.set_metadata("input_size", std::to_string(net.config().input_size));
  const std::string& prior = net.config().input_prior;
  writer.set_metadata("input", prior.empty() ? "linear_rgb" : "linear_rgb+" + prior);
  if (framing != CropFraming{}) writer.set_metadata("framing", framing_text(framing));
  for (const auto& [name, variable] : net.parameters())
    writer.add(name, dims_of(variable.shape()), variable.value().to_host());
  for (const auto& [name, tensor] : net.buffers())
    writer.add(name, dims_of(tensor.shape()), tensor.to_host());
  writer.write_file(path);
}

}  // namespace facetool
