// Convex hull (monotone chain), signed distance to it, and its raster.
#include "libs/face/face_mask.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace facetool {
namespace {

double cross(Point2 o, Point2 a, Point2 b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

std::vector<Point2> convex_hull(std::vector<Point2> points) {
  std::sort(points.begin(), points.end(),
            [](Point2 a, Point2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  if (points.size() < 3) return points;
  std::vector<Point2> hull(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;  // cross > 0 turns: counter-clockwise in (x, y) as stored
}

}  // namespace

std::vector<Point2> face_mask_polygon(const Landmarks68& landmarks, bool extend_forehead) {
  std::vector<Point2> points(landmarks.begin(), landmarks.end());
  if (extend_forehead) {
    const Point2 brows{(landmarks[19].x + landmarks[24].x) / 2, (landmarks[19].y + landmarks[24].y) / 2};
    const Point2 up{brows.x - landmarks[8].x, brows.y - landmarks[8].y};
    for (int i = 17; i <= 26; ++i)
      points.push_back({landmarks[i].x + kForeheadLift * up.x, landmarks[i].y + kForeheadLift * up.y});
  }
  return convex_hull(points);
}

double signed_distance_inside(const std::vector<Point2>& polygon, Point2 p) {
  // Inside a convex polygon the distance to the boundary is the smallest distance to an edge
  // line; outside, the distance to the nearest edge segment.
  double inside = std::numeric_limits<double>::max();
  double outside = std::numeric_limits<double>::max();
  bool is_inside = polygon.size() >= 3;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Point2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
    const double ex = b.x - a.x, ey = b.y - a.y, len = std::hypot(ex, ey);
    if (len == 0) continue;
    const double side = cross(a, b, p) / len;  // > 0: on the interior side
    if (side < 0) is_inside = false;
    inside = std::min(inside, side);
    const double t = std::clamp(((p.x - a.x) * ex + (p.y - a.y) * ey) / (len * len), 0.0, 1.0);
    outside = std::min(outside, std::hypot(p.x - (a.x + t * ex), p.y - (a.y + t * ey)));
  }
  return is_inside ? inside : -outside;
}

ConvexInterior::ConvexInterior(const std::vector<Point2>& polygon) {
  if (polygon.size() < 3) return;  // no interior: every depth is 0
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Point2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
    const double ex = b.x - a.x, ey = b.y - a.y, len = std::hypot(ex, ey);
    if (len == 0) continue;
    lines_.push_back({-ey / len, ex / len, (ey * a.x - ex * a.y) / len});  // cross(a, b, p) / len
  }
}

double ConvexInterior::depth(Point2 p) const {
  if (lines_.empty()) return 0;
  double inside = std::numeric_limits<double>::max();
  for (const Line& l : lines_) {
    const double side = l.nx * p.x + l.ny * p.y + l.c;
    if (side <= 0) return 0;
    inside = std::min(inside, side);
  }
  return inside;
}

bool ConvexInterior::contains(Point2 p) const {
  if (lines_.empty()) return false;
  for (const Line& l : lines_)
    if (l.nx * p.x + l.ny * p.y + l.c < 0) return false;
  return true;
}

std::vector<float> rasterize_mask(const std::vector<Point2>& polygon, int size) {
  std::vector<float> mask(static_cast<size_t>(size) * size, 0.0f);
  const ConvexInterior interior(polygon);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      if (interior.contains({static_cast<double>(x), static_cast<double>(y)}))
        mask[static_cast<size_t>(y) * size + x] = 1.0f;
  return mask;
}

}  // namespace facetool
