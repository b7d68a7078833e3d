// Component image reading for `facetool render`: channel selection, decoding and checks.
#include "apps/facetool/commands/component_images.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "libs/image/resize.h"
#include "libs/io/exr_io.h"
#include "libs/io/image_io.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"

namespace facetool {
namespace {

std::string lower_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

// Every channel of the file (read_exr reads any image: JPEG and PNG itself, others through OpenImageIO).
LayeredImage read_any(const std::string& option, const std::string& path) {
  check_regular_input_file(path, kMaxImageFileBytes, option);
  try {
    return read_exr(path);
  } catch (const Error& e) {
    fail(option, " '", path, "' cannot be read as an image: ", e.what());
  }
}

// The planes named `layer` if the file has all of them, else the channel indices chosen by
// `by_count` (empty: the count is wrong, and `expected` says what would be right).
ComponentImage select(const std::string& option, const std::string& path, const LayeredImage& file,
                      const std::vector<std::string>& layer,
                      std::vector<int> (*by_count)(int channels), const char* expected) {
  std::vector<int> indices;
  for (const std::string& name : layer) indices.push_back(file.find_channel(name));
  if (std::find(indices.begin(), indices.end(), -1) != indices.end())
    indices = by_count(file.channel_count());
  if (indices.empty())
    fail(option, " '", path, "' has ", file.channel_count(), " channel",
         file.channel_count() == 1 ? "" : "s", "; ", option, " needs ", expected);
  ComponentImage image;
  image.option = option;
  image.path = path;
  image.width = file.width;
  image.height = file.height;
  image.channels = static_cast<int>(indices.size());
  image.planes.resize(image.channels * image.plane_size());
  for (int c = 0; c < image.channels; ++c)
    std::copy(file.plane(indices[c]), file.plane(indices[c]) + file.plane_size(), image.plane(c));
  return image;
}

std::vector<int> rgb_or_grey(int channels) {
  if (channels == 3 || channels == 4) return {0, 1, 2};
  if (channels == 1 || channels == 2) return {0, 0, 0};
  return {};
}
std::vector<int> xyz(int channels) {
  if (channels == 3 || channels == 4) return {0, 1, 2};
  return {};
}
std::vector<int> nine(int channels) {
  if (channels == 9) return {0, 1, 2, 3, 4, 5, 6, 7, 8};
  return {};
}
std::vector<int> grey_or_equal_rgb(int channels) {
  if (channels == 1 || channels == 2) return {0};
  if (channels == 3 || channels == 4) return {0, 1, 2};
  return {};
}

}  // namespace

bool is_float_image_file(const std::string& path) {
  const std::string extension = lower_extension(path);
  return extension == ".exr" || extension == ".hdr" || extension == ".pfm";
}

RgbImage read_crop_image(const std::string& path) {
  RgbImage image = read_rgb_image(path, !is_float_image_file(path));
  for (const float v : image.pixels) check(std::isfinite(v), "image '", path, "' holds a NaN or infinite value");
  return image;
}

std::vector<float> read_planar_crop(const std::string& path, int size) {
  const RgbImage image = read_crop_image(path);
  return resize_planar(planar_from_rgb(image), 3, image.width, image.height, size, size);
}

ComponentImage read_albedo_image(const std::string& path) {
  ComponentImage image =
      select("--albedo", path, read_any("--albedo", path), {"albedo.R", "albedo.G", "albedo.B"},
             rgb_or_grey, "RGB (3), RGBA (4) or grey (1) channels");
  if (!is_float_image_file(path))
    for (float& v : image.planes)
      if (std::isfinite(v)) v = srgb_to_linear(v);
  return image;
}

ComponentImage read_normal_image(const std::string& path) {
  ComponentImage image =
      select("--normal", path, read_any("--normal", path), {"normal.X", "normal.Y", "normal.Z"},
             xyz, "3 channels (X, Y, Z; a 4th, alpha, is ignored)");
  if (!is_float_image_file(path))
    for (float& v : image.planes) v = 2.0f * v - 1.0f;
  return image;
}

ComponentImage read_visibility_image(const std::string& path) {
  std::vector<std::string> layer;
  for (int j = 0; j < 9; ++j) layer.push_back("visibility." + std::to_string(j));
  return select("--visibility", path, read_any("--visibility", path), layer, nine,
                "9 channels (SH coefficients v_0..v_8, an EXR)");
}

ComponentImage read_mask_image(const std::string& path) {
  ComponentImage image =
      select("--mask", path, read_any("--mask", path), {"mask"}, grey_or_equal_rgb,
             "1 channel (grey; grey + alpha or R = G = B also work)");
  if (image.channels == 3) {
    const size_t pixels = image.plane_size();
    for (size_t p = 0; p < pixels; ++p)
      check(image.plane(0)[p] == image.plane(1)[p] && image.plane(0)[p] == image.plane(2)[p],
            "--mask '", path, "' is a colour image (R, G, B differ at pixel (", p % image.width,
            ", ", p / image.width, ")); give a grey mask");
    image.channels = 1;
    image.planes.resize(pixels);
  }
  return image;
}

void check_finite(ComponentImage& image, const std::vector<char>& rendered) {
  const size_t pixels = image.plane_size();
  for (int c = 0; c < image.channels; ++c) {
    float* plane = image.plane(c);
    for (size_t p = 0; p < pixels; ++p) {
      if (std::isfinite(plane[p])) continue;
      if (rendered.empty() || rendered[p])
        fail(image.option, " '", image.path, "' holds a NaN or infinite value at pixel (",
             p % image.width, ", ", p / image.width, "), channel ", c,
             "; fix the file or exclude the pixel with --mask");
      plane[p] = 0.0f;
    }
  }
}

}  // namespace facetool
