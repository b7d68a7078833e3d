// Landmarks68: the 68 face landmarks of the iBUG 300-W layout, and which of them are inner points.
#pragma once

#include <array>

#include "libs/image/point2.h"

namespace facetool {

// The 68 landmarks of the Multi-PIE / iBUG 300-W layout: 0-16 jaw line, 17-26 brows,
// 27-35 nose, 36-47 eyes, 48-67 mouth.
constexpr int kLandmarkCount = 68;
using Landmarks68 = std::array<Point2, kLandmarkCount>;

// The 51 inner points (brows, eyes, nose, mouth) name the same place on every face; the 17 jaw
// points are contours that slide with the view.
inline bool is_inner_landmark(int index) { return index >= 17; }

}  // namespace facetool
