// Lights as users say them: a distant light from an azimuth and an elevation, plus ambient.
#pragma once

#include "core/sh/sh_types.h"

namespace facetool::light {

// The unit direction towards a light at `azimuth_deg` and `elevation_deg` in the photo's frame (+X
// the viewer's right, +Y up, +Z towards the viewer): x = sin(az) cos(el), y = sin(el),
// z = cos(az) cos(el). Azimuth 0, elevation 0 is the camera's position; a positive azimuth turns
// the light towards the viewer's right (the subject's left), a positive elevation upwards (the
// sense of `--rotate`'s yaw; docs/relighting.md has a picture).
sh::Vec3 direction_from_angles(double azimuth_deg, double elevation_deg);

// A distant white light from that direction plus a uniform ambient, as 27 SH radiance
// coefficients: with albedo 1 and no occlusion it shades a surface of normal n with
// ambient + intensity max(0, n.l) (to the 9 coefficients' accuracy: 1.06 intensity facing the
// light). Throws facetool::Error for non-finite or negative values, or angles beyond +-360.
sh::RgbLight light_from_direction(double azimuth_deg, double elevation_deg, double ambient, double intensity);

}  // namespace facetool::light
