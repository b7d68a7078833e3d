// The orientation tag of an EXIF block: the TIFF header and the first directory's entries.
#include "libs/io/exif_orientation.h"

namespace facetool {

int exif_orientation(const uint8_t* tiff, size_t size) {
  if (tiff == nullptr || size < 8) return 1;
  const bool little = tiff[0] == 'I' && tiff[1] == 'I';
  if (!little && !(tiff[0] == 'M' && tiff[1] == 'M')) return 1;
  auto u16 = [&](size_t at) -> uint32_t {
    return little ? tiff[at] | (tiff[at + 1] << 8) : (tiff[at] << 8) | tiff[at + 1];
  };
  auto u32 = [&](size_t at) -> uint64_t {
    return little ? u16(at) | (static_cast<uint64_t>(u16(at + 2)) << 16)
                  : (static_cast<uint64_t>(u16(at)) << 16) | u16(at + 2);
  };
  if (u16(2) != 42) return 1;
  const uint64_t directory = u32(4);
  if (directory > size || size - directory < 2) return 1;
  const uint64_t entries = u16(directory);
  for (uint64_t k = 0; k < entries; ++k) {
    const uint64_t entry = directory + 2 + 12 * k;
    if (entry + 12 > size) return 1;
    if (u16(entry) != 0x0112) continue;
    // SHORT (type 3), one value, stored in the entry's first two value bytes.
    if (u16(entry + 2) != 3 || u32(entry + 4) != 1) return 1;
    const uint32_t value = u16(entry + 8);
    return value >= 1 && value <= 8 ? static_cast<int>(value) : 1;
  }
  return 1;
}

}  // namespace facetool
