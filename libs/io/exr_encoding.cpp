// OpenEXR scan-line files written by facetool itself: the header, the offset table and one
// run-length coded chunk per scan line (docs/performance.md: 5x faster than through OpenImageIO).
#include "libs/io/exr_encoding.h"

#include <Imath/half.h>
#include <immintrin.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <set>

#include "core/util/error.h"
#include "core/util/image_limits.h"
#include "core/util/stage_timer.h"

// The pixel loops copy floats and halves as they lie in memory; OpenEXR files are little-endian.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the EXR encoder assumes a little-endian machine");

namespace facetool {

namespace {

// The numbers of the OpenEXR file layout that this encoder uses.
constexpr uint32_t kMagic = 20000630;
constexpr uint32_t kVersion = 2;
constexpr uint32_t kLongNamesFlag = 0x400;  // some name is 32 to 255 bytes long
constexpr size_t kShortNameLimit = 31;
constexpr size_t kNameLimit = 255;
constexpr int32_t kPixelTypeHalf = 1;
constexpr int32_t kPixelTypeFloat = 2;
constexpr uint8_t kCompressionRle = 1;
constexpr uint8_t kIncreasingY = 0;
// A run record repeats one byte 3 to 128 times; a literal record copies 1 to 127 bytes.
constexpr size_t kMinRun = 3;
constexpr size_t kMaxRun = 128;
constexpr size_t kMaxLiteral = 127;

// The attribute names the header always holds; metadata may not reuse them.
const std::set<std::string>& required_attributes() {
  static const std::set<std::string> names = {"channels",  "compression",      "dataWindow",         "displayWindow",
                                              "lineOrder", "pixelAspectRatio", "screenWindowCenter", "screenWindowWidth"};
  return names;
}

class ByteWriter {
 public:
  explicit ByteWriter(std::vector<unsigned char>& out) : out_(out) {}
  template <typename T>
  void integer(T value) {
    using Unsigned = std::make_unsigned_t<T>;
    const Unsigned bits = static_cast<Unsigned>(value);
    for (size_t i = 0; i < sizeof(T); ++i) out_.push_back(static_cast<unsigned char>(bits >> (8 * i)));
  }
  void real(float value) {
    uint32_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    integer(bits);
  }
  void text(const std::string& s) { out_.insert(out_.end(), s.begin(), s.end()); }
  void name(const std::string& s) {
    text(s);
    out_.push_back(0);
  }
  // name, type, size, then the value `fill` writes.
  template <typename Fill>
  void attribute(const std::string& attribute_name, const char* type, Fill fill) {
    name(attribute_name);
    name(type);
    const size_t size_at = out_.size();
    integer(int32_t{0});
    const size_t start = out_.size();
    fill();
    const uint32_t size = static_cast<uint32_t>(out_.size() - start);
    for (size_t i = 0; i < 4; ++i) out_[size_at + i] = static_cast<unsigned char>(size >> (8 * i));
  }

 private:
  std::vector<unsigned char>& out_;
};

// The two preparation steps of OpenEXR's RLE (and ZIP) compression in one pass: the bytes are
// reordered, even-numbered ones first, then odd-numbered ones (s), and each reordered byte after
// the first becomes its difference to the one before plus 128, modulo 256 (out[i] = s[i] -
// s[i - 1] + 128), so smooth data turns into runs of 128.
void prepare(const unsigned char* in, size_t size, unsigned char* out) {
  const size_t half = (size + 1) / 2;  // s[k] = in[2k] for k < half, s[half + k] = in[2k + 1]
  out[0] = in[0];
  for (size_t k = 1; k < half; ++k) out[k] = static_cast<unsigned char>(in[2 * k] - in[2 * k - 2] + 128);
  if (half == size) return;
  out[half] = static_cast<unsigned char>(in[1] - in[2 * half - 2] + 128);
  for (size_t k = 1; half + k < size; ++k)
    out[half + k] = static_cast<unsigned char>(in[2 * k + 1] - in[2 * k - 1] + 128);
}

// Converts n floats, read at `stride`, to half bits rounded to nearest, ties to even (as
// Imath::half rounds: infinities past 65504, subnormals, NaNs kept NaN).
void to_halves_portable(const float* source, size_t stride, size_t n, unsigned char* out) {
  for (size_t x = 0; x < n; ++x, out += 2) {
    const uint16_t bits = Imath::half(source[x * stride]).bits();
    std::memcpy(out, &bits, 2);
  }
}

// The same with the F16C instructions, eight floats at a time, on processors with AVX2 (to_halves;
// Imath's branching conversion is most of the encoding time otherwise).
__attribute__((target("avx,f16c"))) void to_halves_f16c(const float* source, size_t stride, size_t n,
                                                        unsigned char* out) {
  size_t x = 0;
  if (stride == 1)
    for (; x + 8 <= n; x += 8) {
      const __m128i halves = _mm256_cvtps_ph(_mm256_loadu_ps(source + x), _MM_FROUND_TO_NEAREST_INT);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 2 * x), halves);
    }
  to_halves_portable(source + x * stride, stride, n - x, out + 2 * x);
}

void to_halves(const float* source, size_t stride, size_t n, unsigned char* out) {
  // Every processor with AVX2 has F16C (and clang's builtin does not know "f16c").
  static const bool f16c = __builtin_cpu_supports("avx2");
  if (f16c)
    to_halves_f16c(source, stride, n, out);
  else
    to_halves_portable(source, stride, n, out);
}

// Emits `size` bytes as literal records of at most kMaxLiteral bytes each (count negated).
unsigned char* put_literal(const unsigned char* bytes, size_t size, unsigned char* out) {
  while (size > 0) {
    const size_t n = std::min(size, kMaxLiteral);
    *out++ = static_cast<unsigned char>(-static_cast<int>(n));
    std::memcpy(out, bytes, n);
    out += n;
    bytes += n;
    size -= n;
  }
  return out;
}

uint64_t load8(const unsigned char* p) {
  uint64_t v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

constexpr uint64_t kOnes = 0x0101010101010101ull;

// Where the first of three equal bytes lies at or after `from` (`size` if nowhere): eight
// positions per step, a byte of (x ^ y) | (y ^ z) being zero where a triple starts. The lowest
// byte that the zero-byte test flags is always a true zero (borrows only move upward).
size_t next_triple(const unsigned char* in, size_t size, size_t from) {
  size_t j = from;
  for (; j + 10 <= size; j += 8) {
    const uint64_t x = load8(in + j), y = load8(in + j + 1), z = load8(in + j + 2);
    const uint64_t t = (x ^ y) | (y ^ z);
    const uint64_t zero = (t - kOnes) & ~t & (kOnes << 7);
    if (zero) return j + static_cast<size_t>(__builtin_ctzll(zero)) / 8;
  }
  for (; j + 3 <= size; ++j)
    if (in[j] == in[j + 1] && in[j + 1] == in[j + 2]) return j;
  return size;
}

// How many times the byte at `at` repeats from there on, at most `limit`.
size_t run_length(const unsigned char* in, size_t at, size_t limit) {
  const uint64_t repeated = kOnes * in[at];
  size_t k = 1;
  for (; k + 8 <= limit; k += 8) {
    const uint64_t differ = load8(in + at + k) ^ repeated;
    if (differ) return k + static_cast<size_t>(__builtin_ctzll(differ)) / 8;
  }
  while (k < limit && in[at + k] == in[at]) ++k;
  return k;
}

// Run-length codes `size` prepared bytes into `out` (room for size + size / kMaxLiteral + 1
// bytes): every stretch of kMinRun or more equal bytes becomes run records, the bytes between
// them literal records. Returns the coded length.
size_t run_length_code(const unsigned char* in, size_t size, unsigned char* out) {
  unsigned char* const begin = out;
  size_t literal_from = 0;
  for (size_t i = next_triple(in, size, 0); i < size; i = next_triple(in, size, i)) {
    const size_t run = run_length(in, i, std::min(kMaxRun, size - i));
    out = put_literal(in + literal_from, i - literal_from, out);
    *out++ = static_cast<unsigned char>(run - 1);
    *out++ = in[i];
    i += run;
    literal_from = i;
  }
  out = put_literal(in + literal_from, size - literal_from, out);
  return static_cast<size_t>(out - begin);
}

size_t coded_bound(size_t size) { return size + size / kMaxLiteral + 1; }

void check_name(const std::string& path, const char* what, const std::string& name) {
  check(!name.empty(), "cannot write '", path, "': an EXR ", what, " needs a name");
  check(name.size() <= kNameLimit && name.find('\0') == std::string::npos, "cannot write '", path, "': the EXR ", what,
        " name '", name.substr(0, 40), "...' is longer than ", kNameLimit, " bytes or holds a zero byte");
}

}  // namespace

std::vector<unsigned char> exr_rle_compress(const unsigned char* bytes, size_t size) {
  if (size == 0) return {};
  std::vector<unsigned char> prepared(size), coded(coded_bound(size));
  prepare(bytes, size, prepared.data());
  coded.resize(run_length_code(prepared.data(), size, coded.data()));
  return coded;
}

std::vector<unsigned char> encode_exr(const std::string& path, int width, int height,
                                      const std::vector<ExrChannel>& channels,
                                      const std::vector<std::pair<std::string, std::string>>& metadata) {
  StageTimer timer("encode");  // the header, the half conversion and the run-length coding
  check(width > 0 && height > 0 && !channels.empty(), "cannot write '", path, "': the image is empty");
  // Never a file facetool would refuse to read back (which also keeps a line's bytes, at most
  // 32768 x 64 x 4, far inside the chunk size's 32 bits).
  const uint64_t pixels = static_cast<uint64_t>(width) * static_cast<uint64_t>(height);
  check(width <= kMaxImageSide && height <= kMaxImageSide &&
            static_cast<int64_t>(channels.size()) <= kMaxImageChannels && pixels <= kMaxImagePixels &&
            pixels * channels.size() <= kMaxImageValues,
        "cannot write '", path, "': ", width, " x ", height, " pixels with ", channels.size(),
        " channels is more than facetool reads back (docs/input-limits.md)");
  // The format orders channels by name (bytewise); the pixels of a line follow that order.
  std::vector<const ExrChannel*> sorted;
  for (const ExrChannel& c : channels) {
    check_name(path, "channel", c.name);
    check(c.data != nullptr && c.stride >= 1, "cannot write '", path, "': channel '", c.name, "' has no pixels");
    sorted.push_back(&c);
  }
  std::sort(sorted.begin(), sorted.end(), [](const ExrChannel* a, const ExrChannel* b) { return a->name < b->name; });
  for (size_t c = 1; c < sorted.size(); ++c)
    check(sorted[c]->name != sorted[c - 1]->name, "cannot write '", path, "': two channels are named '",
          sorted[c]->name, "'");
  std::set<std::string> metadata_names;
  bool long_names = false;
  for (const ExrChannel* c : sorted) long_names = long_names || c->name.size() > kShortNameLimit;
  for (const auto& [name, value] : metadata) {
    check_name(path, "attribute", name);
    check(!required_attributes().count(name) && metadata_names.insert(name).second, "cannot write '", path,
          "': the EXR attribute '", name, "' is given twice or is one of the format's own");
    check(value.size() < (1u << 31), "cannot write '", path, "': the EXR attribute '", name, "' is too long");
    long_names = long_names || name.size() > kShortNameLimit;
  }

  std::vector<unsigned char> out;
  ByteWriter put(out);
  put.integer(kMagic);
  put.integer(kVersion | (long_names ? kLongNamesFlag : 0u));
  put.attribute("channels", "chlist", [&] {
    for (const ExrChannel* c : sorted) {
      put.name(c->name);
      put.integer(c->half ? kPixelTypeHalf : kPixelTypeFloat);
      put.integer(uint32_t{0});  // pLinear and three reserved bytes
      put.integer(int32_t{1});   // x sampling
      put.integer(int32_t{1});   // y sampling
    }
    put.integer(uint8_t{0});
  });
  put.attribute("compression", "compression", [&] { put.integer(kCompressionRle); });
  for (const char* window : {"dataWindow", "displayWindow"})
    put.attribute(window, "box2i", [&] {
      put.integer(int32_t{0});
      put.integer(int32_t{0});
      put.integer(int32_t{width - 1});
      put.integer(int32_t{height - 1});
    });
  put.attribute("lineOrder", "lineOrder", [&] { put.integer(kIncreasingY); });
  put.attribute("pixelAspectRatio", "float", [&] { put.real(1.0f); });
  put.attribute("screenWindowCenter", "v2f", [&] {
    put.real(0.0f);
    put.real(0.0f);
  });
  put.attribute("screenWindowWidth", "float", [&] { put.real(1.0f); });
  for (const auto& attribute : metadata)
    put.attribute(attribute.first, "string", [&] { put.text(attribute.second); });
  put.integer(uint8_t{0});  // end of the header

  // The offset table (one 64-bit file position per line, filled in below), then the lines.
  const size_t table_at = out.size();
  out.resize(table_at + static_cast<size_t>(height) * sizeof(uint64_t));
  size_t line_bytes = 0;
  for (const ExrChannel* c : sorted) line_bytes += static_cast<size_t>(width) * (c->half ? 2 : 4);
  std::vector<unsigned char> line(line_bytes), prepared(line_bytes), coded(coded_bound(line_bytes));
  for (int y = 0; y < height; ++y) {
    unsigned char* at = line.data();
    const size_t row = static_cast<size_t>(y) * width;
    for (const ExrChannel* c : sorted) {
      const float* source = c->data + row * c->stride;
      if (c->half) {
        to_halves(source, c->stride, width, at);
        at += 2 * static_cast<size_t>(width);
      } else {
        for (int x = 0; x < width; ++x, at += 4) std::memcpy(at, source + x * c->stride, 4);
      }
    }
    prepare(line.data(), line_bytes, prepared.data());
    const size_t coded_size = run_length_code(prepared.data(), line_bytes, coded.data());
    // A reader takes a chunk as coded only when it is shorter than the raw line.
    const bool use_coded = coded_size < line_bytes;
    const uint64_t offset = out.size();
    std::memcpy(out.data() + table_at + static_cast<size_t>(y) * sizeof(uint64_t), &offset, sizeof offset);
    put.integer(int32_t{y});
    put.integer(static_cast<int32_t>(use_coded ? coded_size : line_bytes));
    const unsigned char* chunk = use_coded ? coded.data() : line.data();
    out.insert(out.end(), chunk, chunk + (use_coded ? coded_size : line_bytes));
  }
  return out;
}

}  // namespace facetool
