// Point2: a 2D point in pixel coordinates (x right, y down; pixel (i, j)'s centre at (i, j)).
#pragma once

#include <array>

namespace facetool {

struct Point2 {
  double x = 0, y = 0;
};

// The 68 landmarks of the Multi-PIE / iBUG 300-W layout: 0-16 jaw line, 17-26 brows,
// 27-35 nose, 36-47 eyes, 48-67 mouth.
constexpr int kLandmarkCount = 68;
using Landmarks68 = std::array<Point2, kLandmarkCount>;

// The 51 inner points (brows, eyes, nose, mouth) name the same place on every face; the 17 jaw
// points are contours that slide with the view.
inline bool is_inner_landmark(int index) { return index >= 17; }

}  // namespace facetool
