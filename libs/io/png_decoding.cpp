// PNG files read by libpng, with libpng's errors turned into facetool::Error.
#include "libs/io/png_decoding.h"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <vector>

#include "core/util/error.h"
#include "libs/io/exif_orientation.h"

namespace facetool {
namespace {

// libpng reports a fatal error through this callback, which records the message; libpng then
// jumps back to png_jmpbuf's setjmp.
struct ErrorText {
  char message[256] = "";
};

void on_error(png_structp png, png_const_charp message) {
  auto* text = static_cast<ErrorText*>(png_get_error_ptr(png));
  std::snprintf(text->message, sizeof text->message, "%s", message ? message : "unknown libpng error");
  png_longjmp(png, 1);
}

void on_warning(png_structp, png_const_charp) {}  // warnings (an unknown chunk, a bad CRC in an ancillary chunk) are not printed

class PngReader final : public ImageFileReader {
 public:
  PngReader(const std::string& path, const std::string& kind) : path_(path), kind_(kind) {}
  // Separate from the constructor, so that the destructor releases what a failure leaves open.
  void open() {
    file_ = std::fopen(path_.c_str(), "rb");
    if (file_ == nullptr)
      fail("cannot read ", kind_, " '", path_, "': ", std::strerror(errno), " (check that the file exists and is readable)");
    png_ = png_create_read_struct(PNG_LIBPNG_VER_STRING, &errors_, on_error, on_warning);
    if (png_ != nullptr) info_ = png_create_info_struct(png_);
    check(png_ != nullptr && info_ != nullptr, "cannot read ", kind_, " '", path_, "': libpng could not start");
    if (!read_header())
      fail("cannot read ", kind_, " '", path_, "': not a readable PNG (", errors_.message,
           "); check that the file is a complete image");
  }
  ~PngReader() override {
    if (png_ != nullptr) png_destroy_read_struct(&png_, info_ != nullptr ? &info_ : nullptr, nullptr);
    if (file_ != nullptr) std::fclose(file_);
  }
  PngReader(const PngReader&) = delete;
  PngReader& operator=(const PngReader&) = delete;

  const ImageFileHeader& header() const override { return header_; }

  void read_bytes(uint8_t* out) override {
    check(header_.eight_bit, "internal error: the 16-bit PNG '", path_, "' read as bytes");
    read_rows(out);
  }

  void read_floats(float* out) override {
    const size_t count = static_cast<size_t>(header_.width) * header_.height * header_.channels;
    if (header_.eight_bit) {
      std::vector<uint8_t> bytes(count);
      read_rows(bytes.data());
      for (size_t i = 0; i < count; ++i) out[i] = static_cast<float>(bytes[i]) * (1.0f / 255.0f);
      return;
    }
    std::vector<uint16_t> words(count);  // native byte order (png_set_swap below)
    read_rows(reinterpret_cast<uint8_t*>(words.data()));
    for (size_t i = 0; i < count; ++i) out[i] = static_cast<float>(words[i]) * (1.0f / 65535.0f);
  }

 private:
  void read_rows(uint8_t* out) {
    const size_t stride = static_cast<size_t>(header_.width) * header_.channels * (header_.eight_bit ? 1 : 2);
    rows_.resize(static_cast<size_t>(header_.height));
    for (size_t y = 0; y < rows_.size(); ++y) rows_[y] = out + y * stride;
    if (!decode())
      fail("cannot read the pixels of ", kind_, " '", path_, "': ", errors_.message,
           " (the file is truncated or damaged: replace it)");
  }

  // libpng's work between a setjmp and the jumps back to it: no object with a destructor lives
  // in these two functions.
  bool read_header() {
    if (setjmp(png_jmpbuf(png_))) return false;
    png_init_io(png_, file_);
    png_set_user_limits(png_, 0x7fffffff, 0x7fffffff);  // the caller applies facetool's own limits
    png_read_info(png_, info_);
    const int type = png_get_color_type(png_, info_);
    const int depth = png_get_bit_depth(png_, info_);
    if (type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png_);
    if (type == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png_);
    if (png_get_valid(png_, info_, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png_);
    if (depth == 16) png_set_swap(png_);  // PNG stores big-endian words; x86 reads little-endian
    png_set_interlace_handling(png_);
    png_read_update_info(png_, info_);
    header_.width = png_get_image_width(png_, info_);
    header_.height = png_get_image_height(png_, info_);
    header_.channels = png_get_channels(png_, info_);
    header_.format = "png";
    header_.eight_bit = png_get_bit_depth(png_, info_) == 8;
    static const char* const kNames[4][4] = {{"Y"}, {"Y", "A"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
    for (int c = 0; c < header_.channels && header_.channels <= 4; ++c)
      header_.channel_names.emplace_back(kNames[header_.channels - 1][c]);
#ifdef PNG_eXIf_SUPPORTED
    png_uint_32 exif_size = 0;
    png_bytep exif = nullptr;
    if (png_get_eXIf_1(png_, info_, &exif_size, &exif) != 0)
      header_.orientation = exif_orientation(exif, exif_size);
#endif
    return true;
  }

  bool decode() {
    if (setjmp(png_jmpbuf(png_))) return false;
    png_read_image(png_, rows_.data());  // what follows the pixels (IEND, text) is not read
    return true;
  }

  std::string path_;
  std::string kind_;
  std::FILE* file_ = nullptr;
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
  ErrorText errors_;
  std::vector<png_bytep> rows_;
  ImageFileHeader header_;
};

}  // namespace

std::unique_ptr<ImageFileReader> open_png_file(const std::string& path, const std::string& kind) {
  auto reader = std::make_unique<PngReader>(path, kind);
  reader->open();
  return reader;
}

}  // namespace facetool
