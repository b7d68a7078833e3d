// Contact sheet layout.
#include "libs/synth/contact_sheet.h"

#include <algorithm>
#include <cmath>

#include "core/util/error.h"
#include "core/util/math_constants.h"

namespace facetool {

RgbImage make_contact_sheet(const std::vector<SynthSample>& samples) {
  check(!samples.empty(), "contact sheet: no samples");
  const int w = samples[0].width, h = samples[0].height, gap = 2, columns = 5;
  RgbImage sheet;
  sheet.width = columns * w + (columns - 1) * gap;
  sheet.height = static_cast<int>(samples.size()) * (h + gap) - gap;
  sheet.pixels.assign(static_cast<size_t>(sheet.width) * sheet.height * 3, 1.0f);
  const float inv_sqrt_pi = 1.0f / std::sqrt(static_cast<float>(kPi));
  for (size_t row = 0; row < samples.size(); ++row) {
    const SynthSample& s = samples[row];
    check(s.width == w && s.height == h, "contact sheet: samples differ in size");
    const size_t plane = s.plane();
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t p = static_cast<size_t>(y) * w + x;
        const bool inside = s.mask[p] > 0.5f;
        float cells[5][3];
        for (int c = 0; c < 3; ++c) {
          const float image = s.image[c * plane + p], albedo = s.albedo[c * plane + p];
          cells[0][c] = image;
          cells[1][c] = albedo;
          // Linear mappings are pre-decoded so the PNG's sRGB encoding shows them unchanged.
          cells[2][c] = inside ? srgb_to_linear(0.5f * (s.normal[c * plane + p] + 1.0f)) : 0.0f;
          cells[3][c] = inside && albedo > 0 ? image / albedo : 0.0f;
          cells[4][c] = inside ? srgb_to_linear(s.visibility[p] * inv_sqrt_pi) : 0.0f;
        }
        for (int column = 0; column < columns; ++column) {
          float* out = sheet.at(column * (w + gap) + x, static_cast<int>(row) * (h + gap) + y);
          for (int c = 0; c < 3; ++c) out[c] = cells[column][c];
        }
      }
  }
  return sheet;
}

void write_contact_sheet(const std::string& png_path, const std::vector<SynthSample>& samples) {
  write_png_atomically(png_path, make_contact_sheet(samples));
}

}  // namespace facetool
