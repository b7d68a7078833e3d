// Similarity transforms: composition, inverse, least-squares fit.
#include "libs/image/similarity_transform.h"

#include <cmath>

#include "core/util/error.h"

namespace facetool {

double Similarity2::scale() const { return std::hypot(a, b); }
double Similarity2::angle() const { return std::atan2(b, a); }

Similarity2 Similarity2::inverse() const {
  const double n = a * a + b * b;
  check(n > 0, "similarity transform is degenerate (zero scale)");
  Similarity2 r;
  r.a = a / n;
  r.b = -b / n;
  r.tx = -(r.a * tx - r.b * ty);
  r.ty = -(r.b * tx + r.a * ty);
  return r;
}

Similarity2 Similarity2::then_after(const Similarity2& o) const {
  Similarity2 r;
  r.a = a * o.a - b * o.b;
  r.b = b * o.a + a * o.b;
  const Point2 t = apply({o.tx, o.ty});
  r.tx = t.x;
  r.ty = t.y;
  return r;
}

Similarity2 Similarity2::from(double scale, double angle, double tx, double ty) {
  return {scale * std::cos(angle), scale * std::sin(angle), tx, ty};
}

Similarity2 fit_similarity(const std::vector<Point2>& from, const std::vector<Point2>& to) {
  check(from.size() == to.size() && from.size() >= 2,
        "similarity fit needs two lists of the same size with at least 2 points (got ",
        from.size(), " and ", to.size(), ")");
  const double n = static_cast<double>(from.size());
  Point2 mf, mt;
  for (size_t i = 0; i < from.size(); ++i) {
    mf.x += from[i].x / n;
    mf.y += from[i].y / n;
    mt.x += to[i].x / n;
    mt.y += to[i].y / n;
  }
  double spread = 0, sa = 0, sb = 0;
  for (size_t i = 0; i < from.size(); ++i) {
    const double px = from[i].x - mf.x, py = from[i].y - mf.y;
    const double qx = to[i].x - mt.x, qy = to[i].y - mt.y;
    spread += px * px + py * py;
    sa += px * qx + py * qy;
    sb += px * qy - py * qx;
  }
  check(spread > 1e-12, "similarity fit: the source points are all at one place");
  Similarity2 t;
  t.a = sa / spread;
  t.b = sb / spread;
  t.tx = mt.x - (t.a * mf.x - t.b * mf.y);
  t.ty = mt.y - (t.b * mf.x + t.a * mf.y);
  return t;
}

}  // namespace facetool
