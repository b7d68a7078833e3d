// JPEG files read by libjpeg-turbo, with libjpeg's errors turned into facetool::Error.
#include "libs/io/jpeg_decoding.h"

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <vector>

// jpeglib.h needs size_t and FILE declared first.
#include <jpeglib.h>

#include "core/util/error.h"
#include "libs/io/exif_orientation.h"

namespace facetool {
namespace {

// libjpeg reports a fatal error by calling error_exit, which must not return: it records the
// message and jumps back to the setjmp of the call that started the libjpeg work.
struct ErrorManager {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void on_error(j_common_ptr info) {
  auto* errors = reinterpret_cast<ErrorManager*>(info->err);
  (*info->err->format_message)(info, errors->message);
  std::longjmp(errors->jump, 1);
}

void on_message(j_common_ptr) {}  // warnings are not printed

class JpegReader final : public ImageFileReader {
 public:
  JpegReader(const std::string& path, const std::string& kind) : path_(path), kind_(kind) {}
  // Separate from the constructor, so that the destructor releases what a failure leaves open.
  void open() {
    file_ = std::fopen(path_.c_str(), "rb");
    if (file_ == nullptr)
      fail("cannot read ", kind_, " '", path_, "': ", std::strerror(errno), " (check that the file exists and is readable)");
    info_.err = jpeg_std_error(&errors_.manager);
    errors_.manager.error_exit = on_error;
    errors_.manager.output_message = on_message;
    errors_.message[0] = '\0';
    if (!read_header())
      fail("cannot read ", kind_, " '", path_, "': not a readable JPEG (", errors_.message,
           "); check that the file is a complete image");
  }
  ~JpegReader() override {
    if (created_) jpeg_destroy_decompress(&info_);
    if (file_ != nullptr) std::fclose(file_);
  }
  JpegReader(const JpegReader&) = delete;
  JpegReader& operator=(const JpegReader&) = delete;

  const ImageFileHeader& header() const override { return header_; }

  void read_bytes(uint8_t* out) override {
    if (cmyk_) row_.resize(static_cast<size_t>(header_.width) * 4);
    if (!decode(out))
      fail("cannot read the pixels of ", kind_, " '", path_, "': ", errors_.message,
           " (the file is truncated or damaged: replace it)");
  }

  void read_floats(float* out) override {
    std::vector<uint8_t> bytes(static_cast<size_t>(header_.width) * header_.height * header_.channels);
    read_bytes(bytes.data());
    for (size_t i = 0; i < bytes.size(); ++i) out[i] = static_cast<float>(bytes[i]) * (1.0f / 255.0f);
  }

 private:
  // libjpeg's work between a setjmp and the jumps back to it: no object with a destructor lives
  // in these two functions.
  bool read_header() {
    if (setjmp(errors_.jump)) return false;
    jpeg_create_decompress(&info_);
    created_ = true;
    jpeg_stdio_src(&info_, file_);
    jpeg_save_markers(&info_, JPEG_APP0 + 1, 0xffff);
    jpeg_read_header(&info_, TRUE);
    cmyk_ = info_.jpeg_color_space == JCS_CMYK || info_.jpeg_color_space == JCS_YCCK;
    const bool grey = info_.num_components == 1;
    info_.out_color_space = cmyk_ ? JCS_CMYK : grey ? JCS_GRAYSCALE : JCS_RGB;
    header_.width = info_.image_width;
    header_.height = info_.image_height;
    header_.channels = grey ? 1 : 3;
    header_.format = "jpeg";
    header_.eight_bit = true;
    header_.channel_names = grey ? std::vector<std::string>{"Y"} : std::vector<std::string>{"R", "G", "B"};
    for (jpeg_saved_marker_ptr m = info_.marker_list; m != nullptr; m = m->next)
      if (m->marker == JPEG_APP0 + 1 && m->data_length > 6 && std::memcmp(m->data, "Exif\0\0", 6) == 0) {
        header_.orientation = exif_orientation(m->data + 6, m->data_length - 6);
        break;
      }
    return true;
  }

  bool decode(uint8_t* out) {
    if (setjmp(errors_.jump)) return false;
    jpeg_start_decompress(&info_);
    const size_t stride = static_cast<size_t>(header_.width) * header_.channels;
    while (info_.output_scanline < info_.output_height) {
      uint8_t* target = out + info_.output_scanline * stride;
      JSAMPROW row = cmyk_ ? row_.data() : target;
      if (jpeg_read_scanlines(&info_, &row, 1) != 1) {  // a file source never suspends
        std::strcpy(errors_.message, "the decoder returned no scan line");
        return false;
      }
      if (!cmyk_) continue;
      // Adobe stores ink inverted (255: none), so a channel's light is its value times K's.
      for (int64_t x = 0; x < header_.width; ++x)
        for (int c = 0; c < 3; ++c)
          target[x * 3 + c] = static_cast<uint8_t>((2 * row_[x * 4 + c] * row_[x * 4 + 3] + 255) / 510);
    }
    jpeg_finish_decompress(&info_);
    return true;
  }

  std::string path_;
  std::string kind_;
  std::FILE* file_ = nullptr;
  jpeg_decompress_struct info_{};
  ErrorManager errors_{};
  bool created_ = false;
  bool cmyk_ = false;
  std::vector<uint8_t> row_;
  ImageFileHeader header_;
};

}  // namespace

std::unique_ptr<ImageFileReader> open_jpeg_file(const std::string& path, const std::string& kind) {
  auto reader = std::make_unique<JpegReader>(path, kind);
  reader->open();
  return reader;
}

}  // namespace facetool
