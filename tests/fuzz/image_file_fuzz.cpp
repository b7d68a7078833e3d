// libFuzzer target: facetool's own image readers (libs/io/image_file.h: JPEG through libjpeg-turbo,
// PNG through libpng, the EXIF orientation of both) refuse damaged files with facetool::Error, and
// every image they accept has the size its header gave and an orientation in 1-8. Input: the file's
// bytes. Files that are neither JPEG nor PNG are left alone (OpenImageIO's module would read them).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "core/util/error.h"
#include "libs/io/exif_orientation.h"
#include "libs/io/image_file.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using facetool::fuzz::require;
  // The bytes as an EXIF block too: the walk over its directory must stay inside the block.
  const int orientation = facetool::exif_orientation(data, size);
  require(orientation >= 1 && orientation <= 8, "EXIF orientation outside 1-8");
  const bool jpeg = size >= 3 && data[0] == 0xff && data[1] == 0xd8 && data[2] == 0xff;
  const bool png = size >= 8 && std::memcmp(data, "\x89PNG\r\n\x1a\n", 8) == 0;
  if (!jpeg && !png) return 0;
  static const std::string path = "/tmp/facetool_image_file_fuzz_" + std::to_string(::getpid());
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return 0;
  std::fwrite(data, 1, size, file);
  std::fclose(file);
  try {
    auto reader = facetool::open_image_file(path);
    const facetool::ImageFileHeader& header = reader->header();
    require(header.format == (jpeg ? "jpeg" : "png"), "the format is not the one the bytes say");
    require(header.orientation >= 1 && header.orientation <= 8, "orientation outside 1-8");
    require(header.width > 0 && header.height > 0 && header.channels >= 1 && header.channels <= 4,
            "an accepted header with an impossible size");
    const uint64_t values = static_cast<uint64_t>(header.width) * header.height * header.channels;
    if (values > (uint64_t{1} << 24)) return 0;  // the callers' limits (image_limits.h) refuse far less
    std::vector<float> pixels(values, -1.0f);
    reader->read_floats(pixels.data());
    for (float v : pixels) require(v >= 0.0f && v <= 1.0f, "a decoded value outside [0, 1]");
  } catch (const facetool::Error&) {
  }
  return 0;
}
