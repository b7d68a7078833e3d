// The cpu backend's per-shape convolution algorithm: override, environment, cache file, rule.
#include "backends/cpu/cpu_conv_choice.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

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

// This machine's lines of the cache file: shape key -> algorithm (read once per process).
const std::map<std::string, ConvAlgorithm>& cached_choices() {
  static const std::map<std::string, ConvAlgorithm> choices = [] {
    std::map<std::string, ConvAlgorithm> found;
    const std::string path = conv_cache_path();
    if (path.empty()) return found;
    std::ifstream in(path);
    std::string line, machine, key, name;
    const std::string me = conv_machine_name();
    while (std::getline(in, line)) {
      std::istringstream fields(line);
      if (!(fields >> machine >> key >> name) || machine != me) continue;
      if (const auto algorithm = parse_conv_algorithm(name)) found[key] = *algorithm;
    }
    return found;
  }();
  return choices;
}

}  // namespace

std::string conv_algorithm_name(ConvAlgorithm algorithm) {
  switch (algorithm) {
    case ConvAlgorithm::Im2col: return "im2col";
    case ConvAlgorithm::Winograd: return "winograd";
    case ConvAlgorithm::Dnnl: return "dnnl";
  }
  return "?";
}

std::optional<ConvAlgorithm> parse_conv_algorithm(const std::string& name) {
  for (ConvAlgorithm a : {ConvAlgorithm::Im2col, ConvAlgorithm::Winograd, ConvAlgorithm::Dnnl})
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
  return algorithms;
}

ConvAlgorithm default_conv_algorithm(const ConvGeometry& g, int64_t out_channels) {
  return winograd_applicable(g, out_channels) ? ConvAlgorithm::Winograd : ConvAlgorithm::Im2col;
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
          "' is not a convolution algorithm; use im2col, winograd or dnnl (or unset it)");
    return parsed;
  }();
  if (from_env && applies(*from_env, g, out_channels)) return *from_env;
  const auto& cached = cached_choices();
  const auto found = cached.find(conv_shape_key(g, batch, out_channels));
  if (found != cached.end() && applies(found->second, g, out_channels)) return found->second;
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

void save_conv_choices(const std::vector<std::pair<std::string, ConvAlgorithm>>& choices) {
  const std::string path = conv_cache_path();
  check(!path.empty(), "cannot save convolution choices: no cache file (set FACETOOL_CONV_CACHE, ",
        "XDG_CACHE_HOME or HOME)");
  const std::string me = conv_machine_name();
  std::map<std::string, std::string> replaced;
  for (const auto& [key, algorithm] : choices) replaced[key] = conv_algorithm_name(algorithm);
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
  for (const auto& [key, name] : replaced) text += me + " " + key + " " + name + "\n";
  std::error_code error;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path(), error);
  check(!error, "cannot create the directory of the convolution cache ", path, ": ",
        error.message(), " (set FACETOOL_CONV_CACHE to a writable file)");
  write_text_atomically(path, text);
}

}  // namespace facetool::cpu
