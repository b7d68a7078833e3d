// Image files opened for reading: the header first, then the pixels; JPEG and PNG decoded here, other formats by OpenImageIO.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace facetool {

// What an image file says of itself before its pixels are read.
struct ImageFileHeader {
  int64_t width = 0;
  int64_t height = 0;
  int channels = 0;
  std::string format;      // "jpeg", "png", or OpenImageIO's name of the format ("openexr", "hdr", ...)
  bool floating = false;   // floating-point samples (EXR, HDR): values as stored, no transfer function
  bool eight_bit = false;  // 8-bit samples: read_bytes gives them as stored
  int orientation = 1;     // EXIF orientation, 1-8 (1: none or unknown)
  std::vector<std::string> channel_names;                         // "R", "G", "B", "A", or the file's own
  std::vector<std::pair<std::string, std::string>> attributes;    // string attributes, as the reader names them
};

// One image file open for reading. Every method throws facetool::Error naming the file.
class ImageFileReader {
 public:
  virtual ~ImageFileReader() = default;
  virtual const ImageFileHeader& header() const = 0;
  // Every channel, interleaved, rows top to bottom: width * height * channels values. Bytes only
  // where header().eight_bit; floats for any file, integer samples scaled to [0, 1] (v / 255,
  // v / 65535). Call one of them once.
  virtual void read_bytes(uint8_t* out) = 0;
  virtual void read_floats(float* out) = 0;
};

// Opens `path` and reads its header (no pixels yet). JPEG and PNG files (told by their first
// bytes, whatever their name) are decoded by facetool itself (libjpeg-turbo, libpng); any other
// format by OpenImageIO, whose module (facetool_openimageio.so) is loaded on first use, so that a
// run on JPEG and PNG photos never loads OpenImageIO's ~260 libraries (docs/performance.md).
// `path` must be a regular file (file_checks.h: the caller checks it first). `kind` names the
// file in messages ("cannot read EXR 'a.exr': ...").
std::unique_ptr<ImageFileReader> open_image_file(const std::string& path, const std::string& kind = "image");

// Writes an animated GIF (looping, `frames_per_second`) of 8-bit RGB frames of width x height to
// `path` through OpenImageIO's GIF writer (giflib); throws facetool::Error on failure.
void write_gif_frames(const std::string& path, int width, int height,
                      const std::vector<std::vector<uint8_t>>& frames, int frames_per_second);

}  // namespace facetool
