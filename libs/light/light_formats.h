// Light files: facetool's JSON, SfSNet's 27-value text and DPR's 9-value grey text, both ways.
#pragma once

#include <array>
#include <cstddef>
#include <map>
#include <string>

#include "core/sh/sh_types.h"

namespace facetool::light {

// The largest coefficient magnitude a light may have: far above any real light (an HDR sun
// projects to a few thousand) and far below where rendering it overflows a float. Readers and
// converters refuse values beyond it (and non-finite ones) with a message naming them.
constexpr double kMaxLightCoefficient = 1e6;
// Throws facetool::Error naming `what` unless every value of `light` is finite and within
// +-kMaxLightCoefficient.
void check_light_values(const double* values, size_t count, const std::string& what);


// facetool JSON: {"format": "facetool-light", "version": 1, "coefficients": {"r": [9],
//   "g": [9], "b": [9]}, "metadata": {...}} in the paper's basis and world frame
//   (docs/conventions.md). The renderer's image is albedo / pi * integral L v max(0, w.n) dw.
// SfSNet text: 27 numbers, 9 per channel R, G, B, in SfSNet's order [1, z, x, y, 3z^2-1, xz,
//   yz, x^2-y^2, xy] with the clamped-cosine attenuation folded into its basis, so its
//   shading is sum_i s_i A_l Y_i(n) and its image albedo * shading (no 1/pi).
// DPR text: 9 numbers (grey), one per line, in the paper's order, same attenuated basis as
//   SfSNet, in DPR's camera frame (x right, z up, -y towards the viewer).
// RGB table text: facetool's own coefficients (as in the JSON) as 9 lines of "R G B", line i
//   holding coefficient i of each channel (the SH text `synth --lights` has always read).
// Text files may use commas as separators and '#' comments. Their shape decides the format, so
// that no layout is ever read as another: 9 lines of 3 = rgb-table, 3 lines of 9 = sfsnet
// (as `light convert --to sfsnet` writes it), 9 numbers (one line or one per line) = dpr; 27
// numbers in any other layout are ambiguous and refused unless the format is given.
enum class Format { Facetool, Sfsnet, Dpr, RgbTable };

Format format_from_name(const std::string& name);  // "facetool" | "sfsnet" | "dpr" | "rgb-table"
const char* format_name(Format format);
// By extension and content: .json -> facetool; text by its shape (see above). Throws
// facetool::Error naming the file and the shapes it accepts when the shape is ambiguous.
Format guess_format(const std::string& path);

struct LightFile {
  sh::RgbLight light{};                         // facetool coefficients
  std::map<std::string, std::string> metadata;  // facetool JSON only
};

// Reads a light in any format (guessed when `format` is null) into facetool coefficients.
// Throws facetool::Error naming the file for unreadable files, wrong counts, non-numbers, NaN.
LightFile read_light(const std::string& path, const Format* format = nullptr);
// Parses the text of a light file in `format`; `source` names it in errors (read_light's parser).
LightFile parse_light(const std::string& text, Format format, const std::string& source);
// Writes atomically in `format` (a grey DPR file takes Rec. 601 luma of R, G, B).
void write_light(const std::string& path, const LightFile& light, Format format);
// The text write_light writes (`path` names the file in errors).
std::string encode_light(const std::string& path, const LightFile& light, Format format);

// The conversions behind the text formats (SfSNet: 27 values; DPR: 9).
sh::RgbLight from_sfsnet(const std::array<double, 27>& values);
std::array<double, 27> to_sfsnet(const sh::RgbLight& light);
sh::RgbLight from_dpr(const std::array<double, 9>& values);
std::array<double, 9> to_dpr(const sh::RgbLight& light);

// Each format's own shading at a unit normal given in that format's frame, written from its
// definition; the tests compare them with facetool's renderer on the converted light.
double sfsnet_shading(const std::array<double, 9>& channel, const sh::Vec3& n);
double dpr_shading(const std::array<double, 9>& values, const sh::Vec3& n_dpr);
// Direction conversion between DPR's frame and facetool's.
sh::Vec3 dpr_to_world(const sh::Vec3& d);

}  // namespace facetool::light
