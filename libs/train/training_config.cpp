// Parsing and checking of training configuration files (nlohmann::json).
#include "libs/train/training_config.h"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "core/plugin/network_plugin.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "core/util/json_checks.h"

namespace facetool {
namespace {

using nlohmann::json;

constexpr double kMaxTermWeight = 1e6;

struct Reader {
  const std::string& path;

  void only_keys(const json& object, const std::string& where, const std::set<std::string>& keys) {
    check(object.is_object(), "training config '", path, "': ", where, " must be an object");
    for (auto it = object.begin(); it != object.end(); ++it)
      check(keys.count(it.key()) != 0, "training config '", path, "': unknown key '", it.key(),
            "' in ", where);
  }
  double number(const json& object, const std::string& where, const char* key, double fallback,
                bool required, double lo, double hi) {
    if (!object.contains(key)) {
      check(!required, "training config '", path, "': ", where, " needs '", key, "'");
      return fallback;
    }
    const json& v = object.at(key);
    check(v.is_number(), "training config '", path, "': ", where, ".", key, " must be a number");
    const double x = v.get<double>();
    check(std::isfinite(x) && x >= lo && x <= hi, "training config '", path, "': ", where, ".",
          key, " = ", x, " is outside [", lo, ", ", hi, "]");
    return x;
  }
  int64_t integer(const json& object, const std::string& where, const char* key, int64_t fallback,
                  bool required, int64_t lo, int64_t hi) {
    const double x = number(object, where, key, static_cast<double>(fallback), required,
                            static_cast<double>(lo), static_cast<double>(hi));
    check(x == std::floor(x), "training config '", path, "': ", where, ".", key,
          " must be a whole number");
    return static_cast<int64_t>(x);
  }
  std::string text(const json& object, const std::string& where, const char* key,
                   const std::string& fallback, bool required) {
    if (!object.contains(key)) {
      check(!required, "training config '", path, "': ", where, " needs '", key, "'");
      return fallback;
    }
    check(object.at(key).is_string(), "training config '", path, "': ", where, ".", key,
          " must be a string");
    return object.at(key).get<std::string>();
  }
};

}  // namespace

uint32_t DataSource::provides() const {
  if (kind == "real") return kNeedsImage;
  return kNeedsImage | kNeedsAlbedo | kNeedsNormal | kNeedsVisibility | kNeedsLight;
}

TrainingConfig parse_training_config(const std::string& json_text, const std::string& path) {
  json root;
  try {
    root = json::parse(json_text);
  } catch (const json::exception& e) {
    throw Error("training config '" + path + "' is not valid JSON: " + e.what());
  }
  const std::string duplicate = first_duplicate_json_key(json_text);
  check(duplicate.empty(), "training config '", path, "' gives the key \"", duplicate,
        "\" twice in one object (only one would count); keep one of them");
  Reader r{path};
  TrainingConfig c;
  c.path = path;
  r.only_keys(root, "the file", {"name", "network", "renderer", "optimizer", "steps",
                                 "checkpoint_every", "validation", "seed", "sources"});
  c.name = r.text(root, "the file", "name", "", true);
  if (root.contains("network")) {
    const json& n = root.at("network");
    r.only_keys(n, "network", {"plugin", "width", "input_size", "framing", "input_prior"});
    c.network = r.text(n, "network", "plugin", c.network, false);
    c.width = static_cast<int>(r.integer(n, "network", "width", c.width, false, 2, 4096));
    c.input_size =
        static_cast<int>(r.integer(n, "network", "input_size", c.input_size, false, 2, 4096));
    c.framing = parse_framing(r.text(n, "network", "framing", "v1", false),
                              "training config '" + path + "': network.framing");
    c.input_prior = r.text(n, "network", "input_prior", "", false);
    try {
      input_prior_channels(c.input_prior);
    } catch (const Error& e) {
      throw Error("training config '" + path + "': network.input_prior: " + e.what());
    }
  }
  c.renderer = r.text(root, "the file", "renderer", c.renderer, false);
  const json& o = root.contains("optimizer") ? root.at("optimizer") : json::object();
  r.only_keys(o, "optimizer", {"type", "learning_rate", "beta1", "beta2", "epsilon"});
  check(r.text(o, "optimizer", "type", "adam", false) == "adam", "training config '", path,
        "': optimizer.type must be \"adam\" (the only optimiser facetool has)");
  c.learning_rate = r.number(o, "optimizer", "learning_rate", c.learning_rate, false, 0.0, 10.0);
  c.beta1 = r.number(o, "optimizer", "beta1", c.beta1, false, 0.0, 0.999999);
  c.beta2 = r.number(o, "optimizer", "beta2", c.beta2, false, 0.0, 0.999999999);
  // Adam divides by sqrt(v) + epsilon: 0 gives 0/0 = NaN for a parameter whose gradient is 0.
  c.epsilon = r.number(o, "optimizer", "epsilon", c.epsilon, false, 1e-12, 1.0);
  c.steps = r.integer(root, "the file", "steps", 0, true, 1, int64_t{1} << 40);
  c.checkpoint_every =
      r.integer(root, "the file", "checkpoint_every", c.checkpoint_every, false, 1, int64_t{1} << 40);
  if (root.contains("validation")) {
    const json& v = root.at("validation");
    r.only_keys(v, "validation", {"every", "holdout_every", "batches"});
    c.validation_every = r.integer(v, "validation", "every", c.validation_every, false, 1,
                                   int64_t{1} << 40);
    c.validation_holdout_every = static_cast<int>(
        r.integer(v, "validation", "holdout_every", c.validation_holdout_every, false, 0, 1 << 20));
    c.validation_batches =
        static_cast<int>(r.integer(v, "validation", "batches", c.validation_batches, false, 1, 1 << 20));
  }
  c.seed = static_cast<uint64_t>(r.integer(root, "the file", "seed", 0, false, 0, int64_t{1} << 52));
  check(root.contains("sources") && root.at("sources").is_array() && !root.at("sources").empty(),
        "training config '", path, "' needs \"sources\": a non-empty list of data sources");
  const std::string base = std::filesystem::path(path).parent_path().string();
  std::set<std::string> names;
  for (size_t k = 0; k < root.at("sources").size(); ++k) {
    const json& s = root.at("sources")[k];
    const std::string where = "sources[" + std::to_string(k) + "]";
    r.only_keys(s, where, {"name", "kind", "directory", "batch", "grey_fraction", "relight_fraction", "relight_light", "mirror_fraction",
                        "terms"});
    DataSource d;
    d.name = r.text(s, where, "name", "", true);
    check(names.insert(d.name).second, "training config '", path, "': two sources are called '",
          d.name, "'");
    d.kind = r.text(s, where, "kind", "synthetic", false);
    check(d.kind == "synthetic" || d.kind == "pseudo_labelled" || d.kind == "real",
          "training config '", path, "': ", where, ".kind '", d.kind,
          "' is not synthetic, pseudo_labelled or real");
    d.directory = r.text(s, where, "directory", "", true);
    if (!d.directory.empty() && std::filesystem::path(d.directory).is_relative() && !base.empty())
      d.directory = (std::filesystem::path(base) / d.directory).lexically_normal().string();
    d.batch = static_cast<int>(r.integer(s, where, "batch", d.batch, false, 1, 1 << 16));
    d.grey_fraction = r.number(s, where, "grey_fraction", d.grey_fraction, false, 0.0, 1.0);
    d.relight_fraction = r.number(s, where, "relight_fraction", d.relight_fraction, false, 0.0, 1.0);
    d.mirror_fraction = r.number(s, where, "mirror_fraction", d.mirror_fraction, false, 0.0, 1.0);
    d.relight_light = r.text(s, where, "relight_light", d.relight_light, false);
    check(d.relight_light == "sh" || d.relight_light == "hard", "training config '", path, "': ", where,
          ".relight_light '", d.relight_light, "' is not \"sh\" or \"hard\"");
    check(d.relight_fraction == 0 || d.kind != "real", "training config '", path, "': ", where,
          ".relight_fraction needs labels (the light and normals it relights through); a source of kind "
          "\"real\" has none: label it (facetool pseudo-label) and use kind \"pseudo_labelled\"");
    check(s.contains("terms") && s.at("terms").is_object() && !s.at("terms").empty(),
          "training config '", path, "': ", where, " needs \"terms\": {\"term\": weight, ...}");
    for (auto it = s.at("terms").begin(); it != s.at("terms").end(); ++it) {
      check(it.value().is_number(), "training config '", path, "': ", where, ".terms.", it.key(),
            " needs a numeric weight (e.g. \"", it.key(), "\": 0.2)");
      const double w = it.value().get<double>();
      // A weight beyond 1e6 overflows float losses and gradients (1e308 is infinite in float).
      check(std::isfinite(w) && w >= 0.0 && w <= kMaxTermWeight, "training config '", path,
            "': ", where, ".terms.", it.key(), " has weight ", w, "; weights must be in [0, ",
            kMaxTermWeight, "]");
      d.terms.push_back({it.key(), w});
    }
    c.sources.push_back(std::move(d));
  }
  return c;
}

TrainingConfig read_training_config(const std::string& path) {
  return parse_training_config(read_regular_input_file(path, kMaxTextFileBytes, "training config"),
                                path);
}

void check_terms(const TrainingConfig& config, const std::vector<LossTermInfo>& available) {
  static const char* const kInputNames[] = {"image", "albedo", "normal", "visibility", "light"};
  for (const DataSource& s : config.sources)
    for (const WeightedTerm& t : s.terms) {
      const LossTermInfo* found = nullptr;
      for (const LossTermInfo& info : available)
        if (info.name == t.name) found = &info;
      if (!found) {
        std::string known;
        for (const LossTermInfo& info : available) known += (known.empty() ? "" : ", ") + info.name;
        throw Error("training config '" + config.path + "': source '" + s.name +
                    "' names the unknown loss term '" + t.name + "'; the loaded loss plugins "
                    "provide: " + known);
      }
      const uint32_t missing = found->needs & ~s.provides();
      for (int bit = 0; bit < 5; ++bit)
        check(!(missing & (1u << bit)), "training config '", config.path, "': term '", t.name,
              "' needs the ", kInputNames[bit], " target, which source '", s.name, "' (kind ",
              s.kind, ") does not have; use a pseudo_labelled source (facetool pseudo-label) "
              "or a term that needs only the image");
    }
}

}  // namespace facetool
