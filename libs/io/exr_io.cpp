// EXR files of named float channels: written by exr_encoding, read through OpenImageIO (image_file.h).
#include "libs/io/exr_io.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <memory>

#include "core/util/atomic_file.h"
#include "libs/io/image_file.h"
#include "libs/io/image_io.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "core/util/image_limits.h"

namespace facetool {

namespace {

// The file's own string attributes. OpenImageIO adds its description of the file it read
// ("compression", the "oiio:" names): those are not metadata, and writing them back would ask the
// encoder to store the format's own attribute.
void read_metadata(const ImageFileHeader& header, const std::string& prefix, LayeredImage& image) {
  for (const auto& [name, value] : header.attributes) {
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    if (name == "compression" || name.compare(0, 5, "oiio:") == 0) continue;
    image.metadata.emplace_back(name, value);
  }
}

// "EXR" for .exr files, "image" for the other formats read through the same functions.
std::string kind_of(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".exr" ? "EXR" : "image";
}

std::unique_ptr<ImageFileReader> open_exr(const std::string& path) {
  const std::string kind = kind_of(path);
  check_regular_input_file(path, kMaxImageFileBytes, kind);
  std::unique_ptr<ImageFileReader> input = open_image_file(path, kind);
  const ImageFileHeader& header = input->header();
  check_image_dimensions(path, header.width, header.height, header.channels, kind);
  return input;
}

}  // namespace

std::vector<unsigned char> encode_exr(const std::string& path, const LayeredImage& image) {
  check(image.width > 0 && image.height > 0 && !image.channel_names.empty(),
        "cannot write '", path, "': the image is empty");
  check(image.pixels.size() == image.plane_size() * image.channel_names.size(),
        "cannot write '", path, "': pixel count does not match the size and channels");
  std::vector<ExrChannel> channels;
  for (int c = 0; c < image.channel_count(); ++c) channels.push_back({image.channel_names[c], image.plane(c)});
  return encode_exr(path, image.width, image.height, channels, image.metadata);
}

void write_exr_atomically(const std::string& path, const LayeredImage& image) {
  const std::vector<unsigned char> encoded = encode_exr(path, image);
  write_file_atomically(path, encoded.data(), encoded.size());
}

LayeredImage read_exr(const std::string& path, const std::string& metadata_prefix) {
  auto input = open_exr(path);
  const ImageFileHeader& header = input->header();
  LayeredImage image(static_cast<int>(header.width), static_cast<int>(header.height), header.channel_names);
  std::vector<float> interleaved(image.plane_size() * header.channels);
  input->read_floats(interleaved.data());
  const size_t channels = static_cast<size_t>(header.channels);
  for (size_t c = 0; c < channels; ++c) {
    float* target = image.plane(static_cast<int>(c));
    for (size_t p = 0; p < image.plane_size(); ++p) target[p] = interleaved[p * channels + c];
  }
  read_metadata(header, metadata_prefix, image);
  return image;
}

LayeredImage read_exr_header(const std::string& path, const std::string& metadata_prefix) {
  auto input = open_exr(path);
  const ImageFileHeader& header = input->header();
  LayeredImage image;
  image.width = static_cast<int>(header.width);
  image.height = static_cast<int>(header.height);
  image.channel_names = header.channel_names;
  read_metadata(header, metadata_prefix, image);
  return image;
}

}  // namespace facetool
