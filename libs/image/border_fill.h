// Filling the part of a crop that lies outside the photo with one constant (the mean colour of the
// ring just inside the photo's edge) and cutting the mask there: the same in synth and alignment.
#pragma once

#include <array>
#include <vector>

namespace facetool {

// Width of the ring in pixels for a crop of `crop_size`: max(1, round(crop_size / 32)) (2 at 64,
// 4 at 128), so it covers the same part of the face at any size.
int border_ring_width(int crop_size);

// `coverage` [w*h]: the fraction of each pixel inside the photo (1 inside, 0 outside). The ring is
// the pixels fully inside (coverage 1) within `ring` pixels (Chebyshev distance) of a pixel that
// is not (coverage < 1). Returns the mean of `rgb_planar` ([3][w*h]) over the ring; {0, 0, 0}
// when there is no ring (the photo covers all of the crop, or none of it).
std::array<float, 3> ring_mean_colour(const std::vector<float>& rgb_planar,
                                      const std::vector<float>& coverage, int width, int height,
                                      int ring);

// rgb = coverage * rgb + (1 - coverage) * ring_mean_colour(..., border_ring_width(max(w, h)))
// in place, where `rgb` holds the photo's colour of each pixel's inside part. Returns the fill.
std::array<float, 3> fill_outside_photo(std::vector<float>& rgb_planar,
                                        const std::vector<float>& coverage, int width, int height);

// mask = 0 where coverage < 0.5 (the labels there are not the photo's).
void cut_mask_outside_photo(std::vector<float>& mask, const std::vector<float>& coverage);

}  // namespace facetool
