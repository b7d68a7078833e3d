// Making an SH light non-negative on the sphere (paper section 4.1: "we clamp them").
#pragma once

#include "core/sh/sh_types.h"

namespace facetool::sh {

// Smallest value of one channel of the light over `sample_count` Fibonacci directions.
double min_radiance(const ShCoeffs& channel, int sample_count = 64000);

// Each channel whose radiance dips below zero at any of `sample_count` Fibonacci directions
// is replaced by the projection of max(0, L(w)) (4 pi / N weights, sh_projection.h); channels
// already non-negative there are returned unchanged. Because a degree <= 2 projection of a
// non-negative function can itself ring slightly below zero, the result's minimum is much
// closer to zero but not guaranteed >= 0; callers needing strictness can apply it again.
RgbLight clamp_light_nonnegative(const RgbLight& light, int sample_count = 64000);
ShCoeffs clamp_nonnegative(const ShCoeffs& channel, int sample_count = 64000);

}  // namespace facetool::sh
