// Light files: reading, writing and converting facetool JSON, SfSNet text and DPR text.
#include "libs/light/light_formats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/util/atomic_file.h"
#include "core/sh/clamped_cosine.h"
#include "core/sh/illumination_from_shading.h"
#include "core/sh/sh_basis.h"
#include "core/sh/sh_rotation.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "core/util/math_constants.h"
#include "core/util/json_checks.h"

namespace facetool::light {
namespace {

// SfSNet's position k holds the coefficient of facetool's basis function kSfsnetToPaper[k].
constexpr int kSfsnetToPaper[9] = {0, 2, 3, 1, 6, 7, 5, 8, 4};

// DPR's axes in facetool's frame: x -> X, y -> -Z, z -> Y (a proper rotation).
sh::Mat3 dpr_rotation() { return {{{1, 0, 0}, {0, 0, 1}, {0, -1, 0}}}; }

// The whole file as text (a regular file of a sane size; else a facetool::Error naming it).
std::string read_text(const std::string& path) {
  std::string text = read_regular_input_file(path, kMaxTextFileBytes, "light file");
  protect_input_file(path);
  return text;
}

// The numbers of a light text, one vector per non-empty line.
std::vector<std::vector<double>> parse_rows(const std::string& text, const std::string& path) {
  std::istringstream in(text);
  std::vector<std::vector<double>> rows;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    line = line.substr(0, line.find('#'));
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream words(line);
    std::vector<double> row;
    std::string token;
    while (words >> token) {
      char* end = nullptr;
      const double v = std::strtod(token.c_str(), &end);
      check(end && *end == '\0', "light file '", path, "' line ", line_number, ": '", token,
            "' is not a number");
      check(std::isfinite(v), "light file '", path, "' line ", line_number,
            " holds a non-finite value (", token, ")");
      row.push_back(v);
    }
    if (!row.empty()) rows.push_back(std::move(row));
  }
  return rows;
}

bool has_shape(const std::vector<std::vector<double>>& rows, size_t count, size_t width) {
  if (rows.size() != count) return false;
  for (const auto& row : rows)
    if (row.size() != width) return false;
  return true;
}

size_t number_count(const std::vector<std::vector<double>>& rows) {
  size_t count = 0;
  for (const auto& row : rows) count += row.size();
  return count;
}

std::string shape_text(const std::vector<std::vector<double>>& rows) {
  std::string widths;
  for (const auto& row : rows) widths += (widths.empty() ? "" : ",") + std::to_string(row.size());
  return std::to_string(number_count(rows)) + " numbers on " + std::to_string(rows.size()) +
         (rows.size() == 1 ? " line" : " lines") + " (numbers per line: " + widths + ")";
}

constexpr const char* kTextShapes =
    "27 numbers as 9 lines of 'R G B' (rgb-table, facetool's coefficients) or as 3 lines of 9 "
    "(sfsnet), or 9 numbers (dpr)";

// The format a text file's shape stands for; throws when no single format fits.
Format format_of_shape(const std::vector<std::vector<double>>& rows, const std::string& path) {
  if (has_shape(rows, 9, 3)) return Format::RgbTable;
  if (has_shape(rows, 3, 9)) return Format::Sfsnet;
  if (has_shape(rows, 9, 1) || has_shape(rows, 1, 9)) return Format::Dpr;
  if (number_count(rows) == 27)
    fail("light file '", path, "' holds ", shape_text(rows), ": that layout could be facetool's ",
         "R G B rows or SfSNet's channels; write it as ", kTextShapes,
         ", or name the format (--from / --light-format sfsnet or rgb-table)");
  fail("light file '", path, "' holds ", shape_text(rows), "; expected ", kTextShapes,
       ", or a facetool .json file");
}

std::vector<double> flattened(const std::vector<std::vector<double>>& rows) {
  std::vector<double> values;
  for (const auto& row : rows) values.insert(values.end(), row.begin(), row.end());
  return values;
}

std::string text_of(const std::vector<double>& values, size_t per_line) {
  std::ostringstream out;
  out.precision(9);
  for (size_t i = 0; i < values.size(); ++i)
    out << values[i] << ((i + 1) % per_line == 0 ? "\n" : " ");
  return out.str();
}

// Attenuated-basis coefficients s (shading sum_i s_i A_l Y_i(n), image albedo * shading) to
// facetool light: appendix B turns the shading coefficients S_i = A_l s_i into illumination
// L_i = S_i / A_l = s_i; facetool's image carries 1/pi, so the light is pi * s.
sh::ShCoeffs attenuated_to_light(const sh::ShCoeffs& s) {
  sh::ShCoeffs shading;
  for (int i = 0; i < sh::kCoeffCount; ++i) shading[i] = sh::cosine_band_factor(sh::sh_band(i)) * s[i];
  sh::ShCoeffs light = sh::illumination_from_shading(shading);
  for (double& v : light) v *= kPi;
  return light;
}

sh::ShCoeffs light_to_attenuated(const sh::ShCoeffs& light) {
  sh::ShCoeffs s;
  for (int i = 0; i < sh::kCoeffCount; ++i) s[i] = light[i] / kPi;
  return s;
}

}  // namespace

Format format_from_name(const std::string& name) {
  if (name == "facetool") return Format::Facetool;
  if (name == "sfsnet") return Format::Sfsnet;
  if (name == "dpr") return Format::Dpr;
  if (name == "rgb-table") return Format::RgbTable;
  fail("unknown light format '", name, "'; use facetool, sfsnet, dpr or rgb-table");
}

const char* format_name(Format format) {
  switch (format) {
    case Format::Facetool: return "facetool";
    case Format::Sfsnet: return "sfsnet";
    case Format::Dpr: return "dpr";
    case Format::RgbTable: return "rgb-table";
  }
  return "?";
}

Format guess_format(const std::string& path) {
  if (path.size() >= 5 && path.compare(path.size() - 5, 5, ".json") == 0) return Format::Facetool;
  return format_of_shape(parse_rows(read_text(path), path), path);
}

void check_light_values(const double* values, size_t count, const std::string& what) {
  for (size_t i = 0; i < count; ++i)
    check(std::isfinite(values[i]) && std::abs(values[i]) <= kMaxLightCoefficient, what, ": value ", i, " (",
          values[i], ") is not a finite number within +-", kMaxLightCoefficient, "; lights are far smaller");
}

sh::RgbLight from_sfsnet(const std::array<double, 27>& values) {
  check_light_values(values.data(), values.size(), "SfSNet light");
  sh::RgbLight light{};
  for (int c = 0; c < 3; ++c) {
    sh::ShCoeffs s{};
    for (int k = 0; k < 9; ++k) s[kSfsnetToPaper[k]] = values[c * 9 + k];
    sh::set_light_channel(light, c, attenuated_to_light(s));
  }
  return light;
}

std::array<double, 27> to_sfsnet(const sh::RgbLight& light) {
  std::array<double, 27> values{};
  for (int c = 0; c < 3; ++c) {
    const sh::ShCoeffs s = light_to_attenuated(sh::light_channel(light, c));
    for (int k = 0; k < 9; ++k) values[c * 9 + k] = s[kSfsnetToPaper[k]];
  }
  return values;
}

sh::RgbLight from_dpr(const std::array<double, 9>& values) {
  check_light_values(values.data(), values.size(), "DPR light");
  sh::ShCoeffs s;
  for (int i = 0; i < 9; ++i) s[i] = values[i];
  // Coefficients in DPR's frame, rotated into facetool's frame.
  const sh::ShCoeffs world =
      sh::rotate_coeffs(sh::sh_rotation(dpr_rotation()), attenuated_to_light(s));
  sh::RgbLight light{};
  for (int c = 0; c < 3; ++c) sh::set_light_channel(light, c, world);
  return light;
}

std::array<double, 9> to_dpr(const sh::RgbLight& light) {
  sh::ShCoeffs grey{};
  const double weights[3] = {0.299, 0.587, 0.114};
  for (int c = 0; c < 3; ++c) {
    const sh::ShCoeffs ch = sh::light_channel(light, c);
    for (int i = 0; i < 9; ++i) grey[i] += weights[c] * ch[i];
  }
  sh::Mat3 r = dpr_rotation();
  sh::Mat3 inverse{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) inverse[i][j] = r[j][i];
  const sh::ShCoeffs local = light_to_attenuated(sh::rotate_coeffs(sh::sh_rotation(inverse), grey));
  std::array<double, 9> values{};
  for (int i = 0; i < 9; ++i) values[i] = local[i];
  return values;
}

double sfsnet_shading(const std::array<double, 9>& s, const sh::Vec3& n) {
  const double x = n[0], y = n[1], z = n[2];
  const double a0 = kPi, a1 = 2 * kPi / 3, a2 = kPi / 4;
  const double c1 = a0 / std::sqrt(4 * kPi);
  const double c2 = a1 * std::sqrt(3 / (4 * kPi));
  const double c3 = a2 * 0.5 * std::sqrt(5 / (4 * kPi));
  const double c4 = a2 * 3 * std::sqrt(5 / (12 * kPi));
  const double c5 = a2 * 1.5 * std::sqrt(5 / (12 * kPi));
  const double basis[9] = {c1,          c2 * z,     c2 * x,     c2 * y,      c3 * (2 * z * z - x * x - y * y),
                           c4 * x * z,  c4 * y * z, c5 * (x * x - y * y), c4 * x * y};
  double shading = 0;
  for (int k = 0; k < 9; ++k) shading += s[k] * basis[k];
  return shading;
}

double dpr_shading(const std::array<double, 9>& s, const sh::Vec3& n) {
  const double x = n[0], y = n[1], z = n[2];
  const double att[3] = {kPi, 2 * kPi / 3, kPi / 4};
  const double r = 1 / std::sqrt(kPi);
  const double basis[9] = {0.5 * r * att[0],
                           std::sqrt(3.0) / 2 * r * y * att[1],
                           std::sqrt(3.0) / 2 * r * z * att[1],
                           std::sqrt(3.0) / 2 * r * x * att[1],
                           std::sqrt(15.0) / 2 * r * y * x * att[2],
                           std::sqrt(15.0) / 2 * r * y * z * att[2],
                           std::sqrt(5.0) / 4 * r * (3 * z * z - 1) * att[2],
                           std::sqrt(15.0) / 2 * r * x * z * att[2],
                           std::sqrt(15.0) / 4 * r * (x * x - y * y) * att[2]};
  double shading = 0;
  for (int k = 0; k < 9; ++k) shading += s[k] * basis[k];
  return shading;
}

sh::Vec3 dpr_to_world(const sh::Vec3& d) {
  const sh::Mat3 r = dpr_rotation();
  return {r[0][0] * d[0] + r[0][1] * d[1] + r[0][2] * d[2],
          r[1][0] * d[0] + r[1][1] * d[1] + r[1][2] * d[2],
          r[2][0] * d[0] + r[2][1] * d[1] + r[2][2] * d[2]};
}

LightFile read_light(const std::string& path, const Format* format) {
  const std::string text = read_text(path);
  const bool json = path.size() >= 5 && path.compare(path.size() - 5, 5, ".json") == 0;
  const Format f = format ? *format
                   : json ? Format::Facetool
                          : format_of_shape(parse_rows(text, path), path);
  return parse_light(text, f, path);
}

LightFile parse_light(const std::string& text, Format f, const std::string& path) {
  LightFile file;
  if (f == Format::Facetool) {
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
      // nlohmann's messages start with "[json.exception.<kind>.<id>] "; keep the reason.
      const std::string what = e.what();
      const size_t reason = what.find("] ");
      fail("light file '", path, "' is not valid JSON: ",
           reason == std::string::npos ? what : what.substr(reason + 2),
           "; fix the file or write it again with facetool light convert");
    }
    const std::string duplicate = first_duplicate_json_key(text);
    check(duplicate.empty(), "light file '", path, "' gives the key \"", duplicate,
          "\" twice in one object; keep one of them");
    // Every member is checked for its type before it is read: nlohmann's own type errors would
    // not name the file.
    check(j.is_object() && j.contains("format") && j["format"].is_string() &&
              j["format"].get<std::string>() == "facetool-light",
          "light file '", path,
          "' is not a facetool light (its \"format\" is not \"facetool-light\")");
    const bool version_1 = j.contains("version") && j["version"].is_number_integer() &&
                           j["version"].get<int64_t>() == 1;
    check(version_1, "light file '", path, "' has version ",
          j.contains("version") ? j["version"].dump() : std::string("(none)"),
          "; this facetool reads version 1");
    check(j.contains("coefficients") && j["coefficients"].is_object(), "light file '", path,
          "' has no \"coefficients\" object with members r, g and b");
    const auto& coeffs = j["coefficients"];
    const char* channels[3] = {"r", "g", "b"};
    for (int c = 0; c < 3; ++c) {
      check(coeffs.contains(channels[c]) && coeffs[channels[c]].is_array() &&
                coeffs[channels[c]].size() == 9,
            "light file '", path, "': coefficients.", channels[c], " must hold 9 numbers");
      for (int i = 0; i < 9; ++i) {
        const auto& v = coeffs[channels[c]][i];
        check(v.is_number(), "light file '", path, "': coefficients.", channels[c], "[", i,
              "] is not a number");
        file.light[c * 9 + i] = v.get<double>();
        check(std::isfinite(file.light[c * 9 + i]) && std::abs(file.light[c * 9 + i]) <= kMaxLightCoefficient,
              "light file '", path, "': coefficients.", channels[c], "[", i, "] is not a finite number within +-",
              kMaxLightCoefficient, " (", v.dump(), "); fix the file");
      }
    }
    if (j.contains("metadata") && j["metadata"].is_object())
      for (auto it = j["metadata"].begin(); it != j["metadata"].end(); ++it)
        file.metadata[it.key()] = it.value().is_string() ? it.value().get<std::string>()
                                                         : it.value().dump();
    return file;
  }
  const std::vector<std::vector<double>> rows = parse_rows(text, path);
  const std::vector<double> values = flattened(rows);
  // A named format is trusted for layouts of its own size, except the one layout that belongs
  // to the other 27-number format (9 lines of 3 is never SfSNet, 3 lines of 9 never a table).
  if (f == Format::RgbTable) {
    check(has_shape(rows, 9, 3), "light file '", path, "' holds ", shape_text(rows),
          "; an rgb-table light is 9 lines of 'R G B'");
    for (int i = 0; i < sh::kCoeffCount; ++i)
      for (int c = 0; c < 3; ++c) file.light[c * sh::kCoeffCount + i] = rows[i][c];
    check_light_values(file.light.data(), file.light.size(), "light file '" + path + "'");
  } else if (f == Format::Sfsnet) {
    check(values.size() == 27 && !has_shape(rows, 9, 3), "light file '", path, "' holds ",
          shape_text(rows), "; an SfSNet light has 27 numbers, written as 3 lines of 9");
    std::array<double, 27> a;
    std::copy(values.begin(), values.end(), a.begin());
    check_light_values(a.data(), a.size(), "light file '" + path + "'");
    file.light = from_sfsnet(a);
  } else {
    check(values.size() == 9, "light file '", path, "' holds ", values.size(),
          " numbers; a DPR light has 9");
    std::array<double, 9> a;
    std::copy(values.begin(), values.end(), a.begin());
    check_light_values(a.data(), a.size(), "light file '" + path + "'");
    file.light = from_dpr(a);
  }
  return file;
}

std::string encode_light(const std::string& path, const LightFile& file, Format format) {
  for (double v : file.light)
    check(std::isfinite(v), "refusing to write light '", path, "': it holds a non-finite value");
  if (format == Format::Facetool) {
    // Keys in the order written here (r, g, b), not sorted.
    nlohmann::ordered_json j;
    j["format"] = "facetool-light";
    j["version"] = 1;
    j["basis"] = "real SH, degree <= 2, index l(l+1)+m, orthonormal, no Condon-Shortley phase";
    j["frame"] = "right-handed, +Y up, camera at +Z looking down -Z";
    const char* channels[3] = {"r", "g", "b"};
    for (int c = 0; c < 3; ++c) {
      std::vector<double> v(file.light.begin() + c * 9, file.light.begin() + c * 9 + 9);
      j["coefficients"][channels[c]] = v;
    }
    j["metadata"] = nlohmann::ordered_json::object();
    for (const auto& [key, value] : file.metadata) j["metadata"][key] = value;
    return j.dump(2) + "\n";
  }
  if (format == Format::Sfsnet) {
    const auto values = to_sfsnet(file.light);
    return text_of(std::vector<double>(values.begin(), values.end()), 9);
  }
  if (format == Format::RgbTable) {
    std::vector<double> rows;
    for (int i = 0; i < sh::kCoeffCount; ++i)
      for (int c = 0; c < 3; ++c) rows.push_back(file.light[c * sh::kCoeffCount + i]);
    return text_of(rows, 3);
  }
  const auto values = to_dpr(file.light);
  return text_of(std::vector<double>(values.begin(), values.end()), 1);
}

void write_light(const std::string& path, const LightFile& file, Format format) {
  write_text_atomically(path, encode_light(path, file, format));
}

}  // namespace facetool::light
