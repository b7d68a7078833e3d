// The face mask: the convex hull of the 68 landmarks (paper section 3.2), optionally extended
// over the forehead, as a polygon, a signed distance and a raster.
#pragma once

#include <vector>

#include "libs/face/landmarks68.h"

namespace facetool {

// How far the forehead extension lifts the brow points, as a fraction of the distance from
// the chin (landmark 8) to the brows' centre (mean of 19 and 24), along that direction.
constexpr double kForeheadLift = 0.45;

// Convex hull (positive turns in the stored x, y coordinates: clockwise on screen) of
// the landmarks; with `extend_forehead`, of the landmarks plus the brow points (17-26) lifted
// by kForeheadLift.
std::vector<Point2> face_mask_polygon(const Landmarks68& landmarks, bool extend_forehead);

// Distance of p to the polygon's boundary, positive inside, negative outside (convex polygon
// from face_mask_polygon).
double signed_distance_inside(const std::vector<Point2>& convex_polygon, Point2 p);

// The inside of a convex polygon (from face_mask_polygon), for testing many points: the edges'
// lines are normalised once, so a point costs one multiply-add per edge.
class ConvexInterior {
 public:
  explicit ConvexInterior(const std::vector<Point2>& convex_polygon);
  // max(0, signed_distance_inside(polygon, p)): the depth inside, 0 outside (no distance to the
  // boundary is computed for points outside).
  double depth(Point2 p) const;
  // signed_distance_inside(polygon, p) >= 0: inside or on the boundary.
  bool contains(Point2 p) const;

  struct Line {
    double nx, ny, c;  // nx x + ny y + c: the distance to the edge's line, > 0 inside
  };
  // The edges' lines (none for a polygon of fewer than 3 points): what a shader needs to test
  // points itself (the view page's mask, libs/view).
  const std::vector<Line>& lines() const { return lines_; }

 private:
  std::vector<Line> lines_;
};

// size x size raster: 1 where the pixel centre is inside the polygon, else 0.
std::vector<float> rasterize_mask(const std::vector<Point2>& convex_polygon, int size);

}  // namespace facetool
