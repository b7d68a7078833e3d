// Relighting arithmetic: the two modes, the guarded shading ratio, orbits and the open hemisphere.
#pragma once

#include <cstddef>
#include <string>

#include "core/sh/sh_types.h"

namespace facetool::relight {

// render: albedo x new shading (the model's own picture under the new light);
// ratio:  photo x (new shading / old shading), the division guarded by ratio_factor().
enum class Mode { Render, Ratio };
Mode mode_from_name(const std::string& name);  // "render" | "ratio"; facetool::Error otherwise

// Default guard of the ratio, in linear shading units (a face's shading is typically 0.3..1.5).
constexpr float kDefaultRatioEpsilon = 0.02f;

// The guarded ratio (max(new, 0) + eps) / (max(old, 0) + eps): exactly 1 when new == old
// (so the photo's own light returns the photo), bounded by (max(new, 0) + eps) / eps where the
// old shading is zero or negative (an SH light can dip below zero) instead of dividing by ~0.
float ratio_factor(float new_shading, float old_shading, float epsilon);

// Ratio mode over planar RGB: out = photo x ratio_factor(new, old), all three [3][plane].
void apply_ratio(const float* photo, const float* old_shading, const float* new_shading,
                 size_t plane, float epsilon, float* out);

// SH coefficients of an unoccluded pixel (v(w) = 1 everywhere): 2 sqrt(pi), then zeros. With
// them the renderer gives the open-hemisphere shading (--no-visibility).
sh::ShCoeffs open_visibility();

// Rotation of the light about the vertical (+Y) axis by `degrees` (counter-clockwise seen from
// above, +Z towards +X), in the camera frame (+X right, +Y up, +Z towards the viewer).
sh::Mat3 rotation_about_vertical(double degrees);

// Frame k of an N-frame orbit: the light turned about +Y by 360 k / N degrees.
sh::RgbLight orbit_light(const sh::RgbLight& light, int frame, int frames);

// Multiplies every coefficient by `intensity` (shading is linear in the light).
sh::RgbLight scale_light(const sh::RgbLight& light, double intensity);

}  // namespace facetool::relight
