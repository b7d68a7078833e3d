// Deterministic, nearly uniform direction sets on the unit sphere (spherical Fibonacci lattice).
#pragma once

#include <vector>

#include "core/sh/sh_types.h"

namespace facetool::sh {

// `count` unit directions forming a spherical Fibonacci lattice: sample s (0-based) has
// z = 1 - (2 s + 1) / count (equal-area bands, so every sample stands for 4 pi / count of solid
// angle) and azimuth phi = s * golden_angle with golden_angle = pi (3 - sqrt(5)); x and y follow
// from sin(theta) (cos phi, sin phi). The same count always gives the same directions. The paper
// uses 872 directions for visibility and 64,000 for the illumination loss. count must be > 0.
std::vector<Vec3> fibonacci_sphere(int count);

constexpr int kVisibilitySampleCount = 872;
constexpr int kIlluminationSampleCount = 64000;

}  // namespace facetool::sh
