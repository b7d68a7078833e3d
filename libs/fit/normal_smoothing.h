// Smoothing the fitted normals: a Gaussian over the pixels the fitted head covers.
#pragma once

#include <cstdint>
#include <vector>

namespace facetool {

// Replaces the normal of every pixel the head covers (head[p] != 0) by the Gaussian-weighted mean
// (standard deviation sigma_px pixels, cut at 3 sigma) of the normals of the covered pixels
// around it, renormalised to unit length: pixels off the head neither receive nor give. `normal`
// is planar [3] of width x height; off the head it is left as it is. sigma_px = 0 changes
// nothing. Throws facetool::Error on a size mismatch or a negative or non-finite sigma.
void smooth_normals(std::vector<float>& normal, const std::vector<uint8_t>& head, int width, int height,
                    double sigma_px);

}  // namespace facetool
