// Left-right mirroring of one planar image channel, in place.
#include "libs/image/mirror.h"

#include <utility>

namespace facetool {

void mirror_plane(float* plane, int64_t height, int64_t width, float sign) {
  for (int64_t y = 0; y < height; ++y) {
    float* row = plane + y * width;
    for (int64_t x = 0; x < width / 2; ++x) std::swap(row[x], row[width - 1 - x]);
    if (sign != 1.0f)
      for (int64_t x = 0; x < width; ++x) row[x] *= sign;
  }
}

}  // namespace facetool
