// The cpu backend's measured choices: convolution algorithm per shape, fused batch chunk.
#include "backends/cpu/cpu_conv_choice.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "backends/cpu/cpu_conv.h"
#include "backends/cpu/cpu_winograd.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/parallel_for.h"

namespace facetool::cpu {
namespace {

std::mutex& choice_mutex() {
  static std::mutex m;
  return m;
}

std::optional<ConvAlgorithm>& override_slot() {
  static std::optional<ConvAlgorithm> slot;
  return slot;
}

bool applies(ConvAlgorithm a, const ConvGeometry& g, int64_t out_channels) {
  for (ConvAlgorithm candidate : applicable_conv_algorithms(g, out_channels))
    if (candidate == a) return true;
  return false;
}

std::string cpu_model() {
  std::ifstream info("/proc/cpuinfo");
  std::string line;
  while (std::getline(info, line)) {
    if (line.rfind("model name", 0) == 0) {
      const size_t colon = line.find(':');
      if (colon != std::string::npos) {
        std::string name = line.substr(line.find_first_not_of(' ', colon + 1));
        for (char& c : name)
          if (c == ' ') c = '_';
        return name;
      }
    }
  }
  return "unknown_cpu";
}

// This machine's lines of the cache file: key -> value (read once per process).
const std::map<std::string, std::string>& cached_choices() {
  static const std::map<std::string, std::string> choices =
      read_machine_choices(conv_cache_path(), conv_machine_name());
  return choices;
}

std::optional<int64_t>& chunk_override_slot() {
  static std::optional<int64_t> slot;
  return slot;
}

std::atomic<int64_t>& last_chunk_request() {
  static std::atomic<int64_t> bytes{0};
  return bytes;
}

std::string fused_chunk_key(int64_t bytes_per_image) {
  return "fused_chunk_" + std::to_string(bytes_per_image) + "B";
}

}  // namespace

std::string conv_algorithm_name(ConvAlgorithm algorithm) {
  switch (algorithm) {
    case ConvAlgorithm::Im2col: return "im2col";
    case ConvAlgorithm::Winograd: return "winograd";
    case ConvAlgorithm::Dnnl: return "dnnl";
    case ConvAlgorithm::Direct: return "direct";
  }
  return "?";
}

std::optional<ConvAlgorithm> parse_conv_algorithm(const std::string& name) {
  for (ConvAlgorithm a : {ConvAlgorithm::Im2col, ConvAlgorithm::Winograd, ConvAlgorithm::Dnnl, ConvAlgorithm::Direct})
    if (conv_algorithm_name(a) == name) return a;
  return std::nullopt;
}

std::string conv_shape_key(const ConvGeometry& g, int64_t batch, int64_t out_channels) {
  std::ostringstream key;
  key << "n" << batch << "_c" << g.channels << "_" << g.height << "x" << g.width << "_k"
      << g.kernel << "_s" << g.stride << "_p" << g.pad << "_o" << out_channels;
  return key.str();
}

std::vector<ConvAlgorithm> applicable_conv_algorithms(const ConvGeometry& g,
                                                      int64_t out_channels) {
  std::vector<ConvAlgorithm> algorithms{ConvAlgorithm::Im2col};
  // Winograd's own threshold (>= 16 channels, winograd_applicable) is a speed rule; any channel
  // count is correct.
  if (g.kernel == 3 && g.stride == 1 && g.pad == 1 && g.out_height == g.height &&
      g.out_width == g.width && out_channels >= 1)
    algorithms.push_back(ConvAlgorithm::Winograd);
  algorithms.push_back(ConvAlgorithm::Dnnl);
  if (direct_conv_applicable(g)) algorithms.push_back(ConvAlgorithm::Direct);
  return algorithms;
}

ConvAlgorithm default_conv_algorithm(const ConvGeometry& g, int64_t out_channels) {
  if (winograd_applicable(g, out_channels)) return ConvAlgorithm::Winograd;
  if (out_channels <= kDirectMaxOutChannels && g.kernel > 1 && direct_conv_applicable(g)) return ConvAlgorithm::Direct;
  return ConvAlgorithm::Im2col;
}

ConvAlgorithm chosen_conv_algorithm(const ConvGeometry& g, int64_t batch, int64_t out_channels) {
  {
    std::lock_guard<std::mutex> lock(choice_mutex());
    if (override_slot() && applies(*override_slot(), g, out_channels)) return *override_slot();
  }
  static const std::optional<ConvAlgorithm> from_env = []() -> std::optional<ConvAlgorithm> {
    const char* env = std::getenv("FACETOOL_CONV_ALGORITHM");
    if (!env || !*env) return std::nullopt;
    const auto parsed = parse_conv_algorithm(env);
    check(parsed.has_value(), "FACETOOL_CONV_ALGORITHM='", env,
          "' is not a convolution algorithm; use im2col, winograd, dnnl or direct (or unset it)");
    return parsed;
  }();
  if (from_env && applies(*from_env, g, out_channels)) return *from_env;
  const auto& cached = cached_choices();
  const auto found = cached.find(conv_shape_key(g, batch, out_channels));
  if (found != cached.end())
    if (const auto algorithm = parse_conv_algorithm(found->second); algorithm && applies(*algorithm, g, out_channels))
      return *algorithm;
  return default_conv_algorithm(g, out_channels);
}

void set_conv_algorithm_override(std::optional<ConvAlgorithm> algorithm) {
  std::lock_guard<std::mutex> lock(choice_mutex());
  override_slot() = algorithm;
}

std::string conv_cache_path() {
  if (const char* env = std::getenv("FACETOOL_CONV_CACHE")) return env;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return std::string(xdg) + "/facetool/conv-algorithms.txt";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::string(home) + "/.cache/facetool/conv-algorithms.txt";
  return "";
}

std::string conv_machine_name() {
  return cpu_model() + "/" + std::to_string(parallel_thread_count()) + "threads";
}

std::map<std::string, std::string> read_machine_choices(const std::string& path, const std::string& machine) {
  std::map<std::string, std::string> found;
  if (path.empty()) return found;
  std::ifstream in(path);
  std::string line, who, key, value;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    if ((fields >> who >> key >> value) && who == machine) found[key] = value;
  }
  return found;
}

void save_machine_choices(const std::vector<std::pair<std::string, std::string>>& choices) {
  const std::string path = conv_cache_path();
  check(!path.empty(), "cannot save this machine's measured choices: no cache file (set FACETOOL_CONV_CACHE, ",
        "XDG_CACHE_HOME or HOME)");
  const std::string me = conv_machine_name();
  const std::map<std::string, std::string> replaced(choices.begin(), choices.end());
  std::string text;
  {
    std::ifstream in(path);
    std::string line, machine, key;
    while (std::getline(in, line)) {
      std::istringstream fields(line);
      if ((fields >> machine >> key) && machine == me && replaced.count(key)) continue;
      if (!line.empty()) text += line + "\n";
    }
  }
  for (const auto& [key, value] : replaced) text += me + " " + key + " " + value + "\n";
  std::error_code error;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path(), error);
  check(!error, "cannot create the directory of the measured-choices cache ", path, ": ",
        error.message(), " (set FACETOOL_CONV_CACHE to a writable file)");
  write_text_atomically(path, text);
}

void save_conv_choices(const std::vector<std::pair<std::string, ConvAlgorithm>>& choices) {
  std::vector<std::pair<std::string, std::string>> lines;
  for (const auto& [key, algorithm] : choices) lines.emplace_back(key, conv_algorithm_name(algorithm));
  save_machine_choices(lines);
}

int64_t default_fused_chunk(int64_t bytes_per_image, int64_t batch) {
  return std::clamp<int64_t>(kFusedChunkBytes / std::max<int64_t>(1, bytes_per_image), 1, std::max<int64_t>(1, batch));
}

int64_t chosen_fused_chunk(int64_t bytes_per_image, int64_t batch) {
  last_chunk_request().store(bytes_per_image);
  const int64_t whole = std::max<int64_t>(1, batch);
  auto images = [&](int64_t n) { return n <= 0 ? whole : std::min(n, whole); };
  {
    std::lock_guard<std::mutex> lock(choice_mutex());
    if (chunk_override_slot()) return images(*chunk_override_slot());
  }
  const auto& cached = cached_choices();
  const auto found = cached.find(fused_chunk_key(bytes_per_image));
  if (found != cached.end()) {
    char* end = nullptr;
    const long long n = std::strtoll(found->second.c_str(), &end, 10);
    if (end && *end == '\0' && n >= 0) return images(n);
  }
  return default_fused_chunk(bytes_per_image, batch);
}

void set_fused_chunk_override(std::optional<int64_t> images) {
  std::lock_guard<std::mutex> lock(choice_mutex());
  chunk_override_slot() = images;
}

int64_t last_fused_chunk_request() { return last_chunk_request().load(); }

void save_fused_chunk(int64_t bytes_per_image, int64_t images) {
  save_machine_choices({{fused_chunk_key(bytes_per_image), std::to_string(std::max<int64_t>(0, images))}});
}

}  // namespace facetool::cpu
