// Rotation of normals and SH light from the crop's frame to the photo's.
#include "libs/face/frame_rotation.h"

#include <cmath>

#include "core/sh/sh_rotation.h"

namespace facetool {

sh::Mat3 crop_to_photo_rotation(const Similarity2& photo_to_crop) {
  // photo -> crop is R(theta) in y-down pixels, i.e. Rz(-theta) with +Y up; back is Rz(theta).
  const double t = photo_to_crop.angle(), c = std::cos(t), s = std::sin(t);
  return {{{c, -s, 0.0}, {s, c, 0.0}, {0.0, 0.0, 1.0}}};
}

void rotate_normals_to_photo(float* n, size_t plane, const Similarity2& photo_to_crop) {
  const double t = photo_to_crop.angle();
  const float c = static_cast<float>(std::cos(t)), s = static_cast<float>(std::sin(t));
  for (size_t p = 0; p < plane; ++p) {
    const float x = n[p], y = n[plane + p];
    n[p] = c * x - s * y;
    n[plane + p] = s * x + c * y;
  }
}

void rotate_visibility_to_photo(float* v, size_t plane, const Similarity2& photo_to_crop) {
  const sh::ShMatrix m = sh::sh_rotation(crop_to_photo_rotation(photo_to_crop));
  for (size_t p = 0; p < plane; ++p) {
    sh::ShCoeffs f;
    for (int i = 0; i < sh::kCoeffCount; ++i) f[i] = v[i * plane + p];
    const sh::ShCoeffs g = sh::rotate_coeffs(m, f);
    for (int i = 0; i < sh::kCoeffCount; ++i) v[i * plane + p] = static_cast<float>(g[i]);
  }
}

sh::RgbLight rotate_light_to_photo(const sh::RgbLight& light, const Similarity2& photo_to_crop) {
  return sh::rotate_light(light, crop_to_photo_rotation(photo_to_crop));
}

}  // namespace facetool
