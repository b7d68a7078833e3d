// PNG bytes from 8-bit pixels: PNG's chunk layout (ISO/IEC 15948) around libdeflate's zlib stream.
#include "libs/io/png_encoding.h"

#include <libdeflate.h>

#include <algorithm>
#include <memory>
#include <new>

#include "core/util/error.h"

namespace facetool {
namespace {

void put_u32(std::vector<unsigned char>& out, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<unsigned char>(v >> shift));
}

// Appends a chunk: length, type, data, CRC-32 of type and data.
void put_chunk(std::vector<unsigned char>& out, const char type[4], const unsigned char* data, size_t size) {
  put_u32(out, static_cast<uint32_t>(size));
  const size_t type_at = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data, data + size);
  put_u32(out, libdeflate_crc32(0, out.data() + type_at, size + 4));
}

struct CompressorDeleter {
  void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
};

}  // namespace

std::vector<unsigned char> encode_png8(const std::string& path, int width, int height, int channels,
                                       const uint8_t* pixels) {
  check(width > 0 && height > 0, "cannot write '", path, "': the image is empty");
  check(channels == 3 || channels == 4, "cannot write '", path, "': a PNG of ", channels,
        " channels (facetool writes RGB or RGBA)");
  check(static_cast<uint64_t>(width) * channels < (1ull << 31) && height < (1 << 30), "cannot write '", path,
        "': ", width, " x ", height, " is too large for a PNG");
  const size_t stride = static_cast<size_t>(width) * channels;
  // Filter type 2 ("up") on every row: the first row's "above" is zeros, so it is stored as is.
  std::vector<unsigned char> filtered((stride + 1) * static_cast<size_t>(height));
  for (size_t y = 0; y < static_cast<size_t>(height); ++y) {
    unsigned char* row = &filtered[y * (stride + 1)];
    const uint8_t* here = pixels + y * stride;
    row[0] = 2;
    if (y == 0) {
      std::copy(here, here + stride, row + 1);
      continue;
    }
    const uint8_t* above = here - stride;
    for (size_t x = 0; x < stride; ++x) row[1 + x] = static_cast<unsigned char>(here[x] - above[x]);
  }
  const std::unique_ptr<libdeflate_compressor, CompressorDeleter> compressor(
      libdeflate_alloc_compressor(kPngDeflateLevel));
  if (!compressor) throw std::bad_alloc();
  std::vector<unsigned char> stream(libdeflate_zlib_compress_bound(compressor.get(), filtered.size()));
  const size_t stream_size =
      libdeflate_zlib_compress(compressor.get(), filtered.data(), filtered.size(), stream.data(), stream.size());
  check(stream_size > 0, "cannot write '", path, "': libdeflate could not compress it");

  std::vector<unsigned char> out;
  out.reserve(stream_size + 64);
  const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  out.insert(out.end(), signature, signature + 8);
  std::vector<unsigned char> header;
  put_u32(header, static_cast<uint32_t>(width));
  put_u32(header, static_cast<uint32_t>(height));
  // Bit depth 8; colour type 2 (RGB) or 6 (RGBA); deflate; adaptive filtering; no interlace.
  header.insert(header.end(), {8, static_cast<unsigned char>(channels == 3 ? 2 : 6), 0, 0, 0});
  put_chunk(out, "IHDR", header.data(), header.size());
  put_chunk(out, "IDAT", stream.data(), stream_size);
  put_chunk(out, "IEND", nullptr, 0);
  return out;
}

}  // namespace facetool
