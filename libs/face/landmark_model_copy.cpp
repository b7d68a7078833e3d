// facetool's file of dlib's 68-point shape predictor: layout, checksum, mapping, reading, writing.
//
// Layout (host byte order; the magic's last byte says the format version):
//   "FTLMCPY2"  u32 parts, cascades, trees, splits, pixels, source path length
//   u64 source size  i64 source modification time (ns)  source path bytes  0-3 zero bytes (the
//   arrays start at a multiple of 4, so that a mapped file's floats are aligned)
//   f32 initial_shape  f32 pixel_coordinates  u32 split_pixels  f32 split_thresholds  f32 leaf_values
//   u64 checksum of every section above
#include "libs/face/landmark_model_copy.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstring>

#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"

namespace facetool {
namespace {

constexpr char kMagic[8] = {'F', 'T', 'L', 'M', 'C', 'P', 'Y', '2'};
constexpr uint32_t kMaxParts = 1000, kMaxCascades = 100, kMaxTrees = 10000, kMaxSplits = 1023,
                   kMaxPixels = 100000, kMaxPathBytes = 4096;
constexpr uint64_t kMaxValues = uint64_t{1} << 28;  // 1 GiB of floats in any one array

struct Header {
  uint32_t parts, cascades, trees, splits, pixels, path_bytes;
  uint64_t source_size;
  int64_t source_modified_ns;
};

// A checksum of sections of bytes: four interleaved multiply-xorshift lanes over 8-byte words
// (fast enough that reading ~70 MB pays a few milliseconds for it), folded per section.
class Checksum {
 public:
  void add(const void* data, size_t bytes) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    uint64_t lane[4] = {state_, state_ ^ 0x9e3779b97f4a7c15ull, state_ + 1, ~state_};
    size_t i = 0;
    for (; i + 32 <= bytes; i += 32)
      for (int k = 0; k < 4; ++k) lane[k] = mix(lane[k], load(p + i + 8 * k));
    uint64_t tail[4] = {0, 0, 0, 0};
    std::memcpy(tail, p + i, bytes - i);
    for (int k = 0; k < 4; ++k) lane[k] = mix(lane[k], tail[k]);
    state_ = mix(mix(mix(mix(state_, lane[0]), lane[1]), lane[2]), lane[3] ^ bytes);
  }
  uint64_t value() const { return state_; }

 private:
  static uint64_t load(const unsigned char* p) {
    uint64_t w;
    std::memcpy(&w, p, 8);
    return w;
  }
  static uint64_t mix(uint64_t h, uint64_t w) {
    h = (h ^ w) * 0xff51afd7ed558ccdull;
    return h ^ (h >> 32);
  }
  uint64_t state_ = 0xcbf29ce484222325ull;
};

uint64_t count(const Header& h, int array) {
  const uint64_t per_tree = uint64_t{h.cascades} * h.trees;
  switch (array) {
    case 0: return uint64_t{2} * h.parts;
    case 1: return uint64_t{2} * h.cascades * h.pixels;
    case 2: return per_tree * h.splits * 2;
    case 3: return per_tree * h.splits;
    default: return per_tree * (h.splits + 1) * 2 * h.parts;
  }
}

bool header_sane(const Header& h) {
  if (h.parts == 0 || h.parts > kMaxParts || h.cascades == 0 || h.cascades > kMaxCascades || h.trees == 0 ||
      h.trees > kMaxTrees || h.splits > kMaxSplits || h.pixels == 0 || h.pixels > kMaxPixels ||
      h.path_bytes > kMaxPathBytes)
    return false;
  for (int a = 0; a < 5; ++a)
    if (count(h, a) > kMaxValues) return false;
  return true;
}

// Split pixels in range and leaves a power of two (dlib's requirement), the header sane.
bool arrays_consistent(const LandmarkModelArrays& a) {
  const Header h{a.parts, a.cascades, a.trees, a.splits, a.pixels, 0, 0, 0};
  const uint32_t leaves = a.splits + 1;
  if (!header_sane(h) || (leaves & (leaves - 1)) != 0) return false;
  for (uint64_t i = 0; i < count(h, 2); ++i)
    if (a.split_pixels[i] >= a.pixels) return false;
  return true;
}

// The zero bytes after the source path that put the arrays at a multiple of 4 bytes.
uint32_t padding_after_path(uint32_t path_bytes) {
  return (4 - (sizeof kMagic + sizeof(Header) + path_bytes) % 4) % 4;
}

}  // namespace

LandmarkModelArrays arrays_of(const LandmarkModelCopy& copy) {
  return {copy.parts, copy.cascades, copy.trees, copy.splits, copy.pixels,
          copy.initial_shape.data(), copy.pixel_coordinates.data(), copy.split_pixels.data(),
          copy.split_thresholds.data(), copy.leaf_values.data()};
}

bool LandmarkModelCopy::consistent() const {
  const Header h{parts, cascades, trees, splits, pixels, 0, 0, 0};
  if (!header_sane(h) || initial_shape.size() != count(h, 0) || pixel_coordinates.size() != count(h, 1) ||
      split_pixels.size() != count(h, 2) || split_thresholds.size() != count(h, 3) ||
      leaf_values.size() != count(h, 4))
    return false;
  return arrays_consistent(arrays_of(*this));
}

MappedLandmarkModel::MappedLandmarkModel(MappedLandmarkModel&& other) noexcept
    : base_(other.base_), bytes_(other.bytes_), arrays_(other.arrays_) {
  other.base_ = nullptr;
  other.bytes_ = 0;
}

MappedLandmarkModel& MappedLandmarkModel::operator=(MappedLandmarkModel&& other) noexcept {
  if (this != &other) {
    if (base_) ::munmap(base_, bytes_);
    base_ = other.base_;
    bytes_ = other.bytes_;
    arrays_ = other.arrays_;
    other.base_ = nullptr;
    other.bytes_ = 0;
  }
  return *this;
}

MappedLandmarkModel::~MappedLandmarkModel() {
  if (base_) ::munmap(base_, bytes_);
}

std::optional<LandmarkModelSource> landmark_model_source(const std::string& path) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return std::nullopt;
  LandmarkModelSource source;
  source.path = path;
  source.size = static_cast<uint64_t>(st.st_size);
  source.modified_ns = int64_t{st.st_mtim.tv_sec} * 1000000000 + st.st_mtim.tv_nsec;
  return source;
}

void write_landmark_model_copy(const std::string& path, const LandmarkModelCopy& copy,
                               const LandmarkModelSource& source) {
  check(copy.consistent(), "the landmark model copy for '", path, "' is inconsistent (a bug)");
  check(source.path.size() <= kMaxPathBytes, "landmark model path '", source.path, "' is too long");
  const Header h{copy.parts, copy.cascades, copy.trees, copy.splits, copy.pixels,
                 static_cast<uint32_t>(source.path.size()), source.size, source.modified_ns};
  std::vector<unsigned char> bytes;
  Checksum checksum;
  auto append = [&](const void* data, size_t n) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    bytes.insert(bytes.end(), p, p + n);
    checksum.add(data, n);
  };
  append(kMagic, sizeof kMagic);
  append(&h, sizeof h);
  append(source.path.data(), source.path.size());
  const unsigned char zeros[4] = {0, 0, 0, 0};
  append(zeros, padding_after_path(h.path_bytes));
  append(copy.initial_shape.data(), copy.initial_shape.size() * sizeof(float));
  append(copy.pixel_coordinates.data(), copy.pixel_coordinates.size() * sizeof(float));
  append(copy.split_pixels.data(), copy.split_pixels.size() * sizeof(uint32_t));
  append(copy.split_thresholds.data(), copy.split_thresholds.size() * sizeof(float));
  append(copy.leaf_values.data(), copy.leaf_values.size() * sizeof(float));
  const uint64_t sum = checksum.value();
  const unsigned char* s = reinterpret_cast<const unsigned char*>(&sum);
  bytes.insert(bytes.end(), s, s + sizeof sum);
  write_file_atomically(path, bytes.data(), bytes.size());
}

std::optional<MappedLandmarkModel> map_landmark_model_copy(const std::string& path, const std::string& source_path) {
  if (path.empty()) return std::nullopt;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);  // a FIFO must not block
  if (fd < 0) return std::nullopt;
  // The size of the file opened (not of the name looked up before: the build replaces the copy
  // by a rename, and a mapping longer than its file would fault where the file ends).
  struct stat st;
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) ||
      static_cast<uint64_t>(st.st_size) < sizeof kMagic + sizeof(Header) + sizeof(uint64_t)) {
    ::close(fd);
    return std::nullopt;
  }
  const uint64_t size = static_cast<uint64_t>(st.st_size);
  // MAP_POPULATE: the page cache's pages are mapped in one go (the checksum reads them all).
  void* base = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
  ::close(fd);
  if (base == MAP_FAILED) return std::nullopt;
  MappedLandmarkModel mapped;  // unmapped on every return below but the last
  mapped.base_ = base;
  mapped.bytes_ = size;
  const unsigned char* bytes = static_cast<const unsigned char*>(base);
  size_t at = 0;
  Checksum checksum;
  auto take = [&](uint64_t n) -> const unsigned char* {  // the next n bytes, or nullptr past the end
    if (n > size - at) return nullptr;
    const unsigned char* section = bytes + at;
    checksum.add(section, n);
    at += n;
    return section;
  };
  Header h;
  const unsigned char* magic = take(sizeof kMagic);
  const unsigned char* header = take(sizeof h);
  if (!magic || std::memcmp(magic, kMagic, sizeof kMagic) != 0 || !header) return std::nullopt;
  std::memcpy(&h, header, sizeof h);
  if (!header_sane(h)) return std::nullopt;
  uint64_t expected_bytes = sizeof kMagic + sizeof h + h.path_bytes + padding_after_path(h.path_bytes) + sizeof(uint64_t);
  for (int a = 0; a < 5; ++a) expected_bytes += count(h, a) * 4;
  if (size != expected_bytes) return std::nullopt;
  const unsigned char* path_bytes = take(h.path_bytes);
  LandmarkModelSource made_from;
  made_from.path.assign(reinterpret_cast<const char*>(path_bytes), h.path_bytes);
  made_from.size = h.source_size;
  made_from.modified_ns = h.source_modified_ns;
  // Only a copy of this very file as it is now: otherwise dlib's file is the truth.
  if (!(landmark_model_source(made_from.path) == made_from) || !same_existing_file(made_from.path, source_path))
    return std::nullopt;
  take(padding_after_path(h.path_bytes));
  LandmarkModelArrays& a = mapped.arrays_;
  a.parts = h.parts;
  a.cascades = h.cascades;
  a.trees = h.trees;
  a.splits = h.splits;
  a.pixels = h.pixels;
  // Every section starts at a multiple of 4 bytes of a page-aligned mapping: aligned values.
  a.initial_shape = reinterpret_cast<const float*>(take(count(h, 0) * 4));
  a.pixel_coordinates = reinterpret_cast<const float*>(take(count(h, 1) * 4));
  a.split_pixels = reinterpret_cast<const uint32_t*>(take(count(h, 2) * 4));
  a.split_thresholds = reinterpret_cast<const float*>(take(count(h, 3) * 4));
  a.leaf_values = reinterpret_cast<const float*>(take(count(h, 4) * 4));
  uint64_t stored = 0;
  std::memcpy(&stored, bytes + at, sizeof stored);  // the size check left exactly these 8 bytes
  if (stored != checksum.value() || !arrays_consistent(a)) return std::nullopt;
  return mapped;
}

std::optional<LandmarkModelCopy> read_landmark_model_copy(const std::string& path, const std::string& source_path) {
  const std::optional<MappedLandmarkModel> mapped = map_landmark_model_copy(path, source_path);
  if (!mapped) return std::nullopt;
  const LandmarkModelArrays& a = mapped->arrays();
  const Header h{a.parts, a.cascades, a.trees, a.splits, a.pixels, 0, 0, 0};
  LandmarkModelCopy copy;
  copy.parts = a.parts;
  copy.cascades = a.cascades;
  copy.trees = a.trees;
  copy.splits = a.splits;
  copy.pixels = a.pixels;
  copy.initial_shape.assign(a.initial_shape, a.initial_shape + count(h, 0));
  copy.pixel_coordinates.assign(a.pixel_coordinates, a.pixel_coordinates + count(h, 1));
  copy.split_pixels.assign(a.split_pixels, a.split_pixels + count(h, 2));
  copy.split_thresholds.assign(a.split_thresholds, a.split_thresholds + count(h, 3));
  copy.leaf_values.assign(a.leaf_values, a.leaf_values + count(h, 4));
  return copy;
}

}  // namespace facetool
