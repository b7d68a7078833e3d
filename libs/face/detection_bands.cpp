// Face-size bands and their order-fixed merge (see detection_bands.h).
#include "libs/face/detection_bands.h"

#include <cmath>

namespace facetool {

namespace {
// A band's detector sees faces from its face size to 1.2^3 = 1.73 times it; the next band starts
// at 2 times. Box sizes are the window over the level's scale, so these margins only absorb
// rounding.
constexpr double kBandLow = 0.9, kBandHigh = 1.9;
}  // namespace

bool SizeBand::holds(const ScoredBox& box) const {
  const double s = box.size();
  return s >= kBandLow * face_size && (last || s < kBandHigh * face_size);
}

std::vector<SizeBand> size_bands(double min_face, double shorter_side, double window) {
  std::vector<SizeBand> bands;
  if (!(min_face > 0) || !(shorter_side > 0) || !(window > 0)) return bands;
  const int k = std::max(-2, static_cast<int>(std::floor(std::log2(min_face / window) + 1e-9)));
  // A band exists while its scaled image still holds one window.
  for (double size = window * std::ldexp(1.0, k); shorter_side * window / size >= window; size *= 2)
    bands.push_back({size, false});
  if (!bands.empty()) bands.back().last = true;
  std::reverse(bands.begin(), bands.end());
  return bands;
}

bool same_face(const ScoredBox& a, const ScoredBox& b) {
  const double w = std::min(a.right, b.right) - std::max(a.left, b.left);
  const double h = std::min(a.bottom, b.bottom) - std::max(a.top, b.top);
  if (w <= 0 || h <= 0) return false;
  const double inter = w * h;
  const double area_a = (a.right - a.left) * (a.bottom - a.top);
  const double area_b = (b.right - b.left) * (b.bottom - b.top);
  return inter / (area_a + area_b - inter) > 0.3 || inter / std::min(area_a, area_b) > 0.7;
}

std::vector<std::vector<bool>> merge_in_order(const std::vector<std::vector<ScoredBox>>& groups) {
  std::vector<std::vector<bool>> kept;
  std::vector<ScoredBox> earlier;  // kept boxes of the groups before the current one
  for (const std::vector<ScoredBox>& group : groups) {
    std::vector<bool> keep(group.size(), true);
    for (size_t i = 0; i < group.size(); ++i)
      for (const ScoredBox& e : earlier)
        if (same_face(group[i], e)) {
          keep[i] = false;
          break;
        }
    for (size_t i = 0; i < group.size(); ++i)
      if (keep[i]) earlier.push_back(group[i]);
    kept.push_back(keep);
  }
  return kept;
}

}  // namespace facetool
