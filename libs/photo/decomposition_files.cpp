// Per-crop output files of `facetool infer` and the rows of its contact sheet.
#include "libs/photo/decomposition_files.h"

#include <cmath>
#include <filesystem>

#include "core/util/atomic_file.h"
#include "libs/io/exr_io.h"
#include "libs/io/image_io.h"
#include "libs/light/light_formats.h"
#include "libs/light/light_preview.h"
#include "core/util/error.h"
#include "core/util/math_constants.h"

namespace facetool {
namespace {

// Planar channels [c0, c0 + 3) of image `index` (channels per image `per_image`) as interleaved RGB.
RgbImage planar_to_rgb(const std::vector<float>& planar, int index, int per_image, int c0, int s) {
  const size_t plane = static_cast<size_t>(s) * s;
  return rgb_from_planar(planar.data() + (static_cast<size_t>(index) * per_image + c0) * plane, s, s);
}

RgbImage map_pixels(RgbImage img, float (*f)(float)) {
  for (float& v : img.pixels) v = f(v);
  return img;
}

float encode_normal(float n) { return 0.5f * (n + 1.0f); }

RgbImage ambient_visibility(const Decomposition& d, int index) {
  const int s = d.size;
  const size_t plane = static_cast<size_t>(s) * s;
  RgbImage img;
  img.width = img.height = s;
  img.pixels.resize(plane * 3);
  const float* v0 = d.visibility.data() + static_cast<size_t>(index) * 9 * plane;
  const float unoccluded = static_cast<float>(2.0 * std::sqrt(kPi));
  for (size_t p = 0; p < plane; ++p)
    for (int c = 0; c < 3; ++c) img.pixels[p * 3 + c] = v0[p] / unoccluded;
  return img;
}

FileContents exr_file(const std::string& path, const std::vector<float>& planar, int index,
                      int channels, const std::vector<std::string>& names, int s,
                      const std::string& source) {
  LayeredImage img(s, s, names);
  const size_t count = static_cast<size_t>(channels) * s * s;
  std::copy(planar.begin() + index * count, planar.begin() + (index + 1) * count, img.pixels.begin());
  img.set_metadata("facetool:source", source);
  return {path, encode_exr(path, img)};
}

FileContents png_file(const std::string& path, const RgbImage& image, bool encode_srgb = true) {
  return {path, encode_png(path, image, encode_srgb)};
}

}  // namespace

void write_decomposition(const std::string& folder, const Decomposition& d, int index,
                         const std::vector<float>& input_planar, const std::string& source) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  check(!ec, "cannot create output folder '", folder, "': ", ec.message());
  const int s = d.size;
  auto at = [&](const char* name) { return (std::filesystem::path(folder) / name).string(); };

  light::LightFile light;
  for (int i = 0; i < 27; ++i) light.light[i] = d.light[static_cast<size_t>(index) * 27 + i];
  light.metadata["source"] = source;
  light.metadata["estimated_by"] = "facetool infer";
  const std::string light_text = light::encode_light(at("light.json"), light, light::Format::Facetool);
  std::vector<std::string> vis_names;
  for (int i = 0; i < 9; ++i) vis_names.push_back("visibility." + std::to_string(i));

  // All files of one image are replaced together, and only once every one is written: on a
  // full disk the previous run's files stay as they were.
  write_files_atomically({
      png_file(at("input.png"), planar_to_rgb(input_planar, index, 3, 0, s)),
      png_file(at("reconstruction.png"), planar_to_rgb(d.reconstruction, index, 3, 0, s)),
      png_file(at("albedo.png"), planar_to_rgb(d.albedo, index, 3, 0, s)),
      exr_file(at("albedo.exr"), d.albedo, index, 3, {"R", "G", "B"}, s, source),
      png_file(at("shading.png"), planar_to_rgb(d.shading, index, 3, 0, s)),
      exr_file(at("shading.exr"), d.shading, index, 3, {"R", "G", "B"}, s, source),
      png_file(at("normal.png"), map_pixels(planar_to_rgb(d.normal, index, 3, 0, s), encode_normal),
               false),
      exr_file(at("normal.exr"), d.normal, index, 3, {"X", "Y", "Z"}, s, source),
      png_file(at("visibility.png"), ambient_visibility(d, index), false),
      exr_file(at("visibility.exr"), d.visibility, index, 9, vis_names, s, source),
      {at("light.json"), std::vector<unsigned char>(light_text.begin(), light_text.end())},
      png_file(at("light.png"), light::render_light_preview(light.light, 128).image),
  });
}

RgbImage contact_sheet_row(const Decomposition& d, int index, const std::vector<float>& input_planar) {
  const int s = d.size;
  std::vector<RgbImage> tiles = {
      planar_to_rgb(input_planar, index, 3, 0, s), planar_to_rgb(d.reconstruction, index, 3, 0, s),
      planar_to_rgb(d.albedo, index, 3, 0, s), planar_to_rgb(d.shading, index, 3, 0, s),
      map_pixels(map_pixels(planar_to_rgb(d.normal, index, 3, 0, s), encode_normal), srgb_to_linear),
      map_pixels(ambient_visibility(d, index), srgb_to_linear)};
  const int gap = 2;
  RgbImage row;
  row.width = static_cast<int>(tiles.size()) * (s + gap) - gap;
  row.height = s;
  row.pixels.assign(static_cast<size_t>(row.width) * s * 3, 1.0f);
  for (size_t t = 0; t < tiles.size(); ++t)
    for (int y = 0; y < s; ++y)
      for (int x = 0; x < s; ++x)
        for (int c = 0; c < 3; ++c)
          *(row.at(static_cast<int>(t) * (s + gap) + x, y) + c) = *(tiles[t].at(x, y) + c);
  return row;
}

RgbImage stack_rows(const std::vector<RgbImage>& rows) {
  check(!rows.empty(), "contact sheet: no rows");
  const int gap = 2;
  RgbImage sheet;
  sheet.width = rows[0].width;
  for (const RgbImage& r : rows) sheet.height += r.height + gap;
  sheet.height -= gap;
  sheet.pixels.assign(static_cast<size_t>(sheet.width) * sheet.height * 3, 1.0f);
  int y0 = 0;
  for (const RgbImage& r : rows) {
    std::copy(r.pixels.begin(), r.pixels.end(), sheet.pixels.begin() + static_cast<size_t>(y0) * sheet.width * 3);
    y0 += r.height + gap;
  }
  return sheet;
}

}  // namespace facetool
