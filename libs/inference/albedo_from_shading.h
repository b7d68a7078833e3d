// The albedo that follows from a crop and its shading: the photo divided by the shading, bounded where the shading is dark.
#pragma once

#include <cstddef>

namespace facetool {

// Where the shading is this fraction of the face's median shading or less, the albedo stays the
// network's; from there to kLitShading the photo's ratio fades in.
constexpr float kDarkShading = 0.02f;
constexpr float kLitShading = 0.08f;
// The ratio of the new albedo to the network's is kept within [1 / kMaxAlbedoRatio, kMaxAlbedoRatio].
constexpr float kMaxAlbedoRatio = 5.0f;

// Replaces `albedo` [3][plane] (the network's) by albedo_c r_c, where r_c = image_c / (albedo_c
// shading_c) per colour (for a grey crop, whose three channels are equal in the mask, one r from
// the colours' means: a grey photo says nothing of the albedo's colour), clamped to the bounds
// above and faded to 1 where the shading's mean over the colours is dark relative to its median
// over `mask` (pixels above 0.5); the result is clamped to [0, 1]. Every pixel of the crop is
// updated; where the bounds do not bind, albedo x shading is the crop. `image`, `shading` [3][plane].
void albedo_from_shading(const float* image, const float* shading, const float* mask, size_t plane, float* albedo);

}  // namespace facetool
