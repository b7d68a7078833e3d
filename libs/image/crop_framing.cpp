// CropFraming presets, names and the recorded text form.
#include "libs/image/crop_framing.h"

#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "core/util/error.h"

namespace facetool {

CropFraming v1_framing() { return CropFraming{}; }

CropFraming v2_framing() {
  CropFraming f;
  f.zoom = 1.6;
  f.centre_x = 0.5;
  f.centre_y = 0.456;
  f.border = BorderFill::kRingMean;
  return f;
}

const char* border_fill_name(BorderFill fill) {
  return fill == BorderFill::kRingMean ? "ring-mean" : "edge-repeat";
}

BorderFill parse_border_fill(const std::string& text, const std::string& what) {
  if (text == "edge-repeat") return BorderFill::kEdgeRepeat;
  if (text == "ring-mean") return BorderFill::kRingMean;
  fail(what, ": unknown border fill '", text, "' (use edge-repeat or ring-mean)");
}

namespace {

// The shortest of 15, 16 or 17 significant digits that reads back as the same double.
std::string number(double v) {
  char text[32];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, v);
    if (std::strtod(text, nullptr) == v) break;
  }
  return text;
}

}  // namespace

std::string framing_text(const CropFraming& f) {
  return "zoom " + number(f.zoom) + " centre " + number(f.centre_x) + " " + number(f.centre_y) +
         " border " + border_fill_name(f.border);
}

CropFraming parse_framing(const std::string& text, const std::string& what) {
  if (text == "v1") return v1_framing();
  if (text == "v2") return v2_framing();
  std::istringstream in(text);
  std::string zoom_word, centre_word, border_word, border, rest;
  CropFraming f;
  const bool ok = static_cast<bool>(in >> zoom_word >> f.zoom >> centre_word >> f.centre_x >>
                                    f.centre_y >> border_word >> border) &&
                  !(in >> rest) && zoom_word == "zoom" && centre_word == "centre" &&
                  border_word == "border";
  check(ok, what, ": framing '", text, "' is not 'v1', 'v2' or 'zoom Z centre X Y border ",
        "edge-repeat|ring-mean'");
  check(f.zoom >= 0.25 && f.zoom <= 8, what, ": framing zoom ", f.zoom, " is outside [0.25, 8]");
  check(f.centre_x >= 0 && f.centre_x <= 1 && f.centre_y >= 0 && f.centre_y <= 1, what,
        ": framing centre (", f.centre_x, ", ", f.centre_y, ") is outside [0, 1]");
  f.border = parse_border_fill(border, what);
  return f;
}

}  // namespace facetool
