// Face-size bands: which face sizes a detection searches for a given minimum face size, and the
// merge of the bands' detections that makes a smaller minimum never find fewer faces.
#pragma once

#include <algorithm>
#include <vector>

namespace facetool {

struct ScoredBox {
  double left = 0, top = 0, right = 0, bottom = 0;  // image pixels
  double score = 0;
  double size() const { return std::max(right - left, bottom - top); }
};

// One detector run: the photo scaled by window / face_size, searched at that scale and three
// 5/6 steps below it, so faces of about [face_size, 2 face_size) are found (every larger face
// in the last band, which searches all the way down).
struct SizeBand {
  double face_size = 0;  // photo pixels
  bool last = false;
  double scale(double window) const { return window / face_size; }
  bool holds(const ScoredBox& box) const;  // the box's size belongs to this band
};

// The bands for faces of `min_face` pixels and more in an image whose shorter side is
// `shorter_side` pixels, largest first. The smallest band starts at window x 2^k, the largest
// such size not above min_face (at least window / 4: the photo is enlarged at most 4 times), so
// the bands of a smaller minimum are those of a larger one plus smaller ones.
std::vector<SizeBand> size_bands(double min_face, double shorter_side, double window);

// Two boxes that are the same face: intersection over union above 0.3, or the smaller box
// mostly (70 %) inside the larger.
bool same_face(const ScoredBox& a, const ScoredBox& b);

// Merges groups of detections given in a fixed order (largest band first): a box is kept unless
// it is the same face as a box kept from an earlier group. Boxes within one group were already
// separated by their detector and never suppress each other, so adding groups at the end only
// adds faces. Returns, per group, which of its boxes are kept.
std::vector<std::vector<bool>> merge_in_order(const std::vector<std::vector<ScoredBox>>& groups);

}  // namespace facetool
