// jpeg_is_complete: a marker walk over the file (ITU T.81 B.1), reading it once, sequentially.
#include "libs/io/jpeg_check.h"

#include <cstdint>
#include <fstream>
#include <vector>

namespace facetool {
namespace {

// Buffered sequential reads; -1 at the end of the file.
class ByteReader {
 public:
  explicit ByteReader(const std::string& path) : in_(path, std::ios::binary), buffer_(1 << 20) {}
  int next() {
    if (position_ == filled_) {
      if (!in_) return -1;
      in_.read(reinterpret_cast<char*>(buffer_.data()),
               static_cast<std::streamsize>(buffer_.size()));
      filled_ = static_cast<size_t>(in_.gcount());
      position_ = 0;
      if (filled_ == 0) return -1;
    }
    return buffer_[position_++];
  }
  // Skips `count` bytes; false when the file ends first.
  bool skip(size_t count) {
    for (; count > 0; --count)
      if (next() < 0) return false;
    return true;
  }

 private:
  std::ifstream in_;
  std::vector<uint8_t> buffer_;
  size_t filled_ = 0, position_ = 0;
};

}  // namespace

bool jpeg_is_complete(const std::string& path) {
  ByteReader in(path);
  if (in.next() != 0xFF || in.next() != 0xD8) return true;  // not a JPEG: the decoder says so
  int marker = -1;  // a marker already read by the entropy-data scan
  for (;;) {
    if (marker < 0) {
      int byte = in.next();
      if (byte < 0) return false;
      if (byte != 0xFF) return true;  // not a marker where one belongs: leave it to the decoder
      do byte = in.next();            // fill bytes 0xFF may precede a marker
      while (byte == 0xFF);
      if (byte < 0) return false;
      marker = byte;
    }
    const int m = marker;
    marker = -1;
    if (m == 0xD9) return true;                                // end of image
    if (m == 0x01 || (m >= 0xD0 && m <= 0xD7)) continue;      // no length field
    const int high = in.next(), low = in.next();
    if (high < 0 || low < 0) return false;
    const int length = (high << 8) | low;
    if (length < 2 || !in.skip(static_cast<size_t>(length - 2))) return false;
    if (m != 0xDA) continue;
    // Entropy-coded data of a scan: runs to the next marker that is not a stuffed 0xFF00 or a
    // restart marker.
    for (;;) {
      int byte = in.next();
      if (byte < 0) return false;
      if (byte != 0xFF) continue;
      do byte = in.next();
      while (byte == 0xFF);
      if (byte < 0) return false;
      if (byte == 0x00 || (byte >= 0xD0 && byte <= 0xD7)) continue;
      marker = byte;
      break;
    }
  }
}

}  // namespace facetool
