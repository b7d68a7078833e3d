// facetool's file of dlib's 68-point shape predictor: layout, checksum, reading and writing.
//
// Layout (host byte order; the magic's last byte says the format version):
//   "FTLMCPY1"  u32 parts, cascades, trees, splits, pixels, source path length
//   u64 source size  i64 source modification time (ns)  source path bytes
//   f32 initial_shape  f32 pixel_coordinates  u32 split_pixels  f32 split_thresholds  f32 leaf_values
//   u64 checksum of every section above
#include "libs/face/landmark_model_copy.h"

#include <sys/stat.h>

#include <cstring>
#include <fstream>

#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"

namespace facetool {
namespace {

constexpr char kMagic[8] = {'F', 'T', 'L', 'M', 'C', 'P', 'Y', '1'};
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

}  // namespace

bool LandmarkModelCopy::consistent() const {
  const Header h{parts, cascades, trees, splits, pixels, 0, 0, 0};
  if (!header_sane(h) || (leaves() & (leaves() - 1)) != 0) return false;
  if (initial_shape.size() != count(h, 0) || pixel_coordinates.size() != count(h, 1) ||
      split_pixels.size() != count(h, 2) || split_thresholds.size() != count(h, 3) ||
      leaf_values.size() != count(h, 4))
    return false;
  for (uint32_t index : split_pixels)
    if (index >= pixels) return false;
  return true;
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

std::optional<LandmarkModelCopy> read_landmark_model_copy(const std::string& path, const std::string& source_path) {
  if (path.empty()) return std::nullopt;
  const std::optional<LandmarkModelSource> self = landmark_model_source(path);
  if (!self) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  Checksum checksum;
  auto read = [&](void* data, size_t n) {
    if (!in.read(static_cast<char*>(data), static_cast<std::streamsize>(n))) return false;
    checksum.add(data, n);
    return true;
  };
  char magic[sizeof kMagic];
  Header h;
  if (!read(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof kMagic) != 0 || !read(&h, sizeof h) ||
      !header_sane(h))
    return std::nullopt;
  LandmarkModelSource made_from;
  made_from.path.resize(h.path_bytes);
  made_from.size = h.source_size;
  made_from.modified_ns = h.source_modified_ns;
  if (!read(made_from.path.data(), h.path_bytes)) return std::nullopt;
  // Only a copy of this very file as it is now: otherwise dlib's file is the truth.
  if (!(landmark_model_source(made_from.path) == made_from) || !same_existing_file(made_from.path, source_path))
    return std::nullopt;
  uint64_t expected_bytes = sizeof kMagic + sizeof h + h.path_bytes + sizeof(uint64_t);
  for (int a = 0; a < 5; ++a) expected_bytes += count(h, a) * 4;
  if (self->size != expected_bytes) return std::nullopt;
  LandmarkModelCopy copy;
  copy.parts = h.parts;
  copy.cascades = h.cascades;
  copy.trees = h.trees;
  copy.splits = h.splits;
  copy.pixels = h.pixels;
  copy.initial_shape.resize(count(h, 0));
  copy.pixel_coordinates.resize(count(h, 1));
  copy.split_pixels.resize(count(h, 2));
  copy.split_thresholds.resize(count(h, 3));
  copy.leaf_values.resize(count(h, 4));
  if (!read(copy.initial_shape.data(), copy.initial_shape.size() * 4) ||
      !read(copy.pixel_coordinates.data(), copy.pixel_coordinates.size() * 4) ||
      !read(copy.split_pixels.data(), copy.split_pixels.size() * 4) ||
      !read(copy.split_thresholds.data(), copy.split_thresholds.size() * 4) ||
      !read(copy.leaf_values.data(), copy.leaf_values.size() * 4))
    return std::nullopt;
  const uint64_t computed = checksum.value();
  uint64_t stored = 0;
  if (!in.read(reinterpret_cast<char*>(&stored), sizeof stored) || stored != computed || !copy.consistent())
    return std::nullopt;
  return copy;
}

}  // namespace facetool
