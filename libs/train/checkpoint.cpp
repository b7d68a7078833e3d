// Checkpoint files: one safetensors file holding network, optimiser and run position.
#include "libs/train/checkpoint.h"

#include <cmath>

#include "libs/model/safetensors.h"
#include "core/util/error.h"

namespace facetool {
namespace {

constexpr const char* kFormat = "facetool-checkpoint";

std::vector<int64_t> dims(const Shape& s) {
  std::vector<int64_t> d;
  for (int i = 0; i < s.rank(); ++i) d.push_back(s[i]);
  return d;
}

void restore(const SafeTensors& file, const std::string& path, const std::string& name,
             const Tensor& into) {
  check(file.contains(name), "checkpoint '", path, "' has no tensor '", name,
        "': it was written for another network or is damaged");
  const SafeTensors::Entry& e = file.entry(name);
  check(e.shape == dims(into.shape()), "checkpoint '", path, "': tensor '", name,
        "' has another shape than the network's ", into.shape().str());
  const std::vector<float> values = file.floats(name);
  const bool variance = name.size() >= 4 && name.compare(name.size() - 4, 4, "_var") == 0;
  for (size_t k = 0; k < values.size(); ++k)
    check(std::isfinite(values[k]) && (!variance || values[k] >= 0.0f), "checkpoint '", path,
          "': tensor '", name, "' holds ", std::isfinite(values[k]) ? "a negative variance" :
          "a NaN or infinite value", " at element ", k, " (a damaged file: use an earlier copy)");
  into.copy_from_host(values);
}

const std::string& meta(const SafeTensors& file, const std::string& path, const char* key) {
  auto it = file.metadata().find(key);
  check(it != file.metadata().end(), "checkpoint '", path, "' has no '", key,
        "' metadata: it is not a facetool checkpoint");
  return it->second;
}

int64_t meta_int(const SafeTensors& file, const std::string& path, const char* key) {
  const std::string& text = meta(file, path, key);
  try {
    size_t used = 0;
    const long long v = std::stoll(text, &used);
    if (used == text.size()) return v;
  } catch (const std::exception&) {
  }
  throw Error("checkpoint '" + path + "': metadata '" + key + "' = '" + text +
              "' is not a whole number");
}

CheckpointState state_of(const SafeTensors& file, const std::string& path) {
  check(meta(file, path, "format") == kFormat, "'", path, "' is a ", meta(file, path, "format"),
        " file, not a facetool checkpoint");
  check(meta(file, path, "format_version") == "1", "checkpoint '", path, "' has format version ",
        meta(file, path, "format_version"), "; this facetool reads version 1");
  CheckpointState s;
  s.step = meta_int(file, path, "step");
  s.seed = static_cast<uint64_t>(meta_int(file, path, "seed"));
  s.config_name = meta(file, path, "config");
  s.architecture = meta(file, path, "architecture");
  s.network.width = static_cast<int>(meta_int(file, path, "width"));
  s.network.input_size = static_cast<int>(meta_int(file, path, "input_size"));
  if (auto it = file.metadata().find("input_prior"); it != file.metadata().end()) s.network.input_prior = it->second;
  return s;
}

}  // namespace

void save_checkpoint(const std::string& path, const NetworkPlugin& network,
                     const AdamOptimizer& optimizer, const CheckpointState& state) {
  SafeTensorsWriter w;
  w.set_metadata("format", kFormat);
  w.set_metadata("format_version", "1");
  w.set_metadata("step", std::to_string(state.step));
  w.set_metadata("seed", std::to_string(state.seed));
  w.set_metadata("config", state.config_name);
  w.set_metadata("architecture", state.architecture);
  w.set_metadata("width", std::to_string(state.network.width));
  w.set_metadata("input_size", std::to_string(state.network.input_size));
  if (!state.network.input_prior.empty()) w.set_metadata("input_prior", state.network.input_prior);
  for (const auto& [name, p] : network.parameters())
    w.add("network/" + name, dims(p.shape()), p.value().to_host());
  for (const auto& [name, t] : network.buffers()) w.add("network/" + name, dims(t.shape()), t.to_host());
  for (const auto& [name, t] : optimizer.state()) w.add("adam/" + name, dims(t.shape()), t.to_host());
  w.write_file(path);
}

CheckpointState read_checkpoint_state(const std::string& path) {
  return state_of(SafeTensors::read_file(path), path);
}

CheckpointState load_checkpoint(const std::string& path, NetworkPlugin& network,
                                AdamOptimizer& optimizer) {
  const SafeTensors file = SafeTensors::read_file(path);
  const CheckpointState s = state_of(file, path);
  for (const auto& [name, p] : network.parameters()) restore(file, path, "network/" + name, p.value());
  for (const auto& [name, t] : network.buffers()) restore(file, path, "network/" + name, t);
  for (const auto& [name, t] : optimizer.state()) restore(file, path, "adam/" + name, t);
  optimizer.set_steps_taken(s.step);
  return s;
}

bool is_checkpoint(const SafeTensors& file) {
  const auto& metadata = file.metadata();
  const auto format = metadata.find("format");
  return format != metadata.end() && format->second == kFormat;
}

void load_checkpoint_network(const SafeTensors& file, const std::string& path, NetworkPlugin& network) {
  for (const auto& [name, p] : network.parameters()) restore(file, path, "network/" + name, p.value());
  for (const auto& [name, t] : network.buffers()) restore(file, path, "network/" + name, t);
}

}  // namespace facetool
