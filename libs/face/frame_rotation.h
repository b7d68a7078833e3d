// Vectors back into the photo's frame: the alignment's in-plane rotation turns normals and the
// light about the view axis (docs/photos.md, "Paste-back").
#pragma once

#include <cstddef>

#include "libs/image/similarity_transform.h"
#include "core/sh/sh_types.h"

namespace facetool {

// The alignment rotates the photo by angle() in image (y down) coordinates; in the camera frame
// (+X right, +Y up, +Z to the viewer) a crop direction d is the photo direction Rz(angle) d.
sh::Mat3 crop_to_photo_rotation(const Similarity2& photo_to_crop);

// Rotates planar normals [3][plane] (camera frame of the crop) into the photo's frame.
void rotate_normals_to_photo(float* planar_normals, size_t plane, const Similarity2& photo_to_crop);

// Rotates planar visibility [9][plane] (each pixel's SH coefficients of the directions it sees
// light from, in the crop's frame) into the photo's frame.
void rotate_visibility_to_photo(float* planar_visibility, size_t plane, const Similarity2& photo_to_crop);

// The light (27 SH coefficients) of the crop expressed in the photo's frame.
sh::RgbLight rotate_light_to_photo(const sh::RgbLight& light, const Similarity2& photo_to_crop);

}  // namespace facetool
