// Similarity2: a 2D similarity (rotation, uniform scale, translation) and its least-squares fit.
#pragma once

#include <vector>

#include "libs/image/point2.h"

namespace facetool {

// q = [a -b; b a] p + t, in pixel coordinates (y down). scale = |(a, b)|; angle = atan2(b, a)
// is the rotation in the image's own (y down) coordinates, i.e. clockwise as seen on screen.
struct Similarity2 {
  double a = 1, b = 0, tx = 0, ty = 0;

  Point2 apply(Point2 p) const { return {a * p.x - b * p.y + tx, b * p.x + a * p.y + ty}; }
  double scale() const;
  double angle() const;
  Similarity2 inverse() const;
  // (this * other)(p) = this(other(p)).
  Similarity2 then_after(const Similarity2& other) const;
  static Similarity2 from(double scale, double angle, double tx, double ty);
};

// The similarity minimising sum |T(from_i) - to_i|^2 (closed form, no reflection); the point
// lists must have the same size, at least 2 points and not all equal. Throws facetool::Error.
Similarity2 fit_similarity(const std::vector<Point2>& from, const std::vector<Point2>& to);

}  // namespace facetool
