// Left-right mirroring of one planar image channel, in place.
#pragma once

#include <cstdint>

namespace facetool {

// Reverses each row of the `height` x `width` plane at `plane` (column x takes column
// width - 1 - x) and multiplies every value by `sign` (-1 for a component that changes sign in
// the mirror: a normal's x, an SH coefficient odd in x).
void mirror_plane(float* plane, int64_t height, int64_t width, float sign = 1.0f);

}  // namespace facetool
