// dlib's HOG face detector over one octave, and searching each pyramid level only where it is
// not one flat grey (the padding around a photo): dlib code, included by the detector's engine
// (in both its compilations, among dlib's headers: face_detector_engine.cpp) and by its test.
#pragma once

#include <algorithm>
#include <vector>

#include <dlib/image_processing.h>
#include <dlib/image_processing/frontal_face_detector.h>

#include "libs/face/detector_code.h"

namespace facetool {
namespace FACETOOL_DETECTOR_CODE {

// The same filters as `all_levels`, over one octave of pyramid levels (1, 5/6, (5/6)^2, (5/6)^3:
// one octave of face sizes).
inline dlib::frontal_face_detector one_octave(const dlib::frontal_face_detector& all_levels) {
  dlib::frontal_face_detector::image_scanner_type scanner;
  scanner.copy_configuration(all_levels.get_scanner());
  scanner.set_max_pyramid_levels(4);
  std::vector<dlib::frontal_face_detector::feature_vector_type> filters;
  for (unsigned long i = 0; i < all_levels.num_detectors(); ++i) filters.push_back(all_levels.get_w(i));
  return dlib::frontal_face_detector(scanner, all_levels.get_overlap_tester(), filters);
}

// The smallest rectangle outside which `image` is all one grey (that of its top-left pixel);
// empty when the whole image is that grey.
inline dlib::rectangle varied_area(const dlib::array2d<unsigned char>& image) {
  if (image.size() == 0) return dlib::rectangle();
  const unsigned char flat = image[0][0];
  auto row_varies = [&](long y, long x0, long x1) {
    for (long x = x0; x <= x1; ++x)
      if (image[y][x] != flat) return true;
    return false;
  };
  long top = 0, bottom = image.nr() - 1;
  while (top <= bottom && !row_varies(top, 0, image.nc() - 1)) ++top;
  if (top > bottom) return dlib::rectangle();
  while (!row_varies(bottom, 0, image.nc() - 1)) --bottom;
  long left = image.nc() - 1, right = 0;
  for (long y = top; y <= bottom; ++y) {
    for (long x = 0; x < left; ++x)
      if (image[y][x] != flat) {
        left = x;
        break;
      }
    for (long x = image.nc() - 1; x > right; --x)
      if (image[y][x] != flat) {
        right = x;
        break;
      }
  }
  return dlib::rectangle(left, top, std::max(left, right), bottom);
}

// dlib's `detector(image, found, threshold)`, searching each pyramid level only around its
// varied area. Where an image is one grey, HOG's features are exactly zero (no gradient), and a
// window of zero features scores minus its filter's bias (-3.27 at best for dlib's frontal
// filters): at any threshold above that, it is never a face. Each level is built from the whole
// image as dlib builds it, cropped to its varied area grown by kReachCells HOG cells (and half a
// filter with Windows::every; the crop's left and top on the cell grid, so that its cells are the
// level's own), and searched alone: every window centred on a cell of the crop is scored with the
// level's own features. With Windows::every every other window sees only zero features, and the
// boxes, scores and their order are dlib's (HogScan test; two boxes of exactly equal score could
// come in the other order). At a threshold that lets windows of zero features through, dlib's
// own search runs.
class HogScan {
 public:
  // A box of a crop whose top-left pixel is (left, top) of the level (a whole number of cells),
  // in the level's pixels. dlib maps a window's cells to pixels adding half a cell away from 0,
  // so the move is made before that half cell.
  static dlib::rectangle moved(const dlib::rectangle& box, long left, long top, long cell) {
    auto move = [half = cell / 2](long x, long by) {
      const long unrounded = (x > 0 ? x - half : x + half) + by;
      return unrounded >= 0 ? unrounded + half : unrounded - half;
    };
    return dlib::rectangle(move(box.left(), left), move(box.top(), top), move(box.right(), left),
                           move(box.bottom(), top));
  }

  using Scanner = dlib::frontal_face_detector::image_scanner_type;

  // Which windows are scored: every one that dlib scores and that could reach the threshold, or
  // (the detector's choice) only those centred within kReachCells of the varied area: a window
  // centred further out has more than half of itself in the flat grey, and no face of 300
  // UTKFace photos, 500 padded yaleb-dev photos or the example photos hangs out of its photo by
  // more than 22 % of its box. It skips half a filter more of the padding on every side.
  enum class Windows { every, centred_on_the_varied_area };

  explicit HogScan(const dlib::frontal_face_detector& detector, Windows windows = Windows::every)
      : detector_(detector), windows_(windows) {}

  void operator()(const dlib::array2d<unsigned char>& image, std::vector<dlib::rect_detection>& found,
                  double threshold) {
    const Scanner& whole = detector_.get_scanner();
    const unsigned long dims = whole.get_num_dimensions();
    for (unsigned long i = 0; i < detector_.num_detectors(); ++i)
      if (detector_.get_w(i)(dims) + threshold <= 0) {  // zero windows would be faces
        detector_(image, found, threshold);
        return;
      }
    // The number of levels, as dlib counts them.
    typename Scanner::pyramid_type pyramid;
    unsigned long levels = 0;
    dlib::rectangle rect = dlib::get_rect(image);
    do {
      rect = pyramid.rect_down(rect);
      ++levels;
    } while (rect.width() >= whole.get_min_pyramid_layer_width() &&
             rect.height() >= whole.get_min_pyramid_layer_height() && levels < whole.get_max_pyramid_levels());

    // Each filter's detections over every level, in dlib's order (its own sort), then dlib's
    // non-maximum suppression over all filters.
    std::vector<std::vector<std::pair<double, dlib::rectangle>>> per_filter(detector_.num_detectors());
    dlib::array2d<unsigned char> level, next, crop;
    const long cell = static_cast<long>(whole.get_cell_size());
    // The crop's margin: the features of kReachCells cells around a varied pixel may be non-zero,
    // and a window centred on the crop's last cell reaches half a filter beyond it.
    const auto& filter = detector_.get_processed_w(0).get_detect_argument().filters[0];
    const long margin_cells =
        (windows_ == Windows::every ? (std::max(filter.nr(), filter.nc()) + 1) / 2 : 0) + kReachCells;
    Scanner level_scanner;  // one level at a time
    level_scanner.copy_configuration(whole);
    level_scanner.set_max_pyramid_levels(1);
    for (unsigned long l = 0; l < levels; ++l) {
      if (l == 1) pyramid(image, level);
      if (l > 1) {
        pyramid(level, next);
        dlib::swap(level, next);
      }
      const dlib::array2d<unsigned char>& at = l == 0 ? image : level;
      const dlib::rectangle varied = varied_area(at);
      if (varied.is_empty()) continue;
      const long margin = margin_cells * cell;
      const long left = std::max(0L, (varied.left() - margin) / cell * cell);
      const long top = std::max(0L, (varied.top() - margin) / cell * cell);
      const long right = std::min(at.nc() - 1, varied.right() + margin + kTailCells * cell);
      const long bottom = std::min(at.nr() - 1, varied.bottom() + margin);
      if (left == 0 && top == 0 && right == at.nc() - 1 && bottom == at.nr() - 1) {
        level_scanner.load(at);
      } else {
        crop.set_size(bottom - top + 1, right - left + 1);
        for (long y = top; y <= bottom; ++y)
          std::copy(&at[y][left], &at[y][left] + crop.nc(), &crop[y - top][0]);
        level_scanner.load(crop);
      }
      std::vector<std::pair<double, dlib::rectangle>> dets;
      for (unsigned long i = 0; i < detector_.num_detectors(); ++i) {
        level_scanner.detect(detector_.get_processed_w(i).get_detect_argument(), dets,
                              detector_.get_w(i)(dims) + threshold);
        for (const std::pair<double, dlib::rectangle>& d : dets)
          per_filter[i].push_back({d.first, pyramid.rect_up(moved(d.second, left, top, cell), l)});
      }
    }
    std::vector<dlib::rect_detection> all;
    for (unsigned long i = 0; i < per_filter.size(); ++i) {
      std::sort(per_filter[i].rbegin(), per_filter[i].rend(), dlib::impl::compare_pair_rect);
      const double bias = detector_.get_w(i)(dims);
      for (const std::pair<double, dlib::rectangle>& d : per_filter[i]) {
        dlib::rect_detection r;
        r.detection_confidence = d.first - bias;
        r.weight_index = i;
        r.rect = d.second;
        all.push_back(r);
      }
    }
    if (detector_.num_detectors() > 1) std::sort(all.rbegin(), all.rend());
    found.clear();
    const dlib::test_box_overlap& overlaps = detector_.get_overlap_tester();
    for (const dlib::rect_detection& d : all)
      if (std::none_of(found.begin(), found.end(),
                       [&](const dlib::rect_detection& f) { return overlaps(f.rect, d.rect); }))
        found.push_back(d);
  }

 private:
  // A cell's HOG features come from the gradients of its pixels and the pixels next to them
  // (bilinear votes into the cells around) and from its neighbours' (2 x 2 block normalisation):
  // a varied pixel's reach is two cells and a pixel; three hold it.
  static constexpr long kReachCells = 3;
  // dlib filters eight windows at a time and the last few of a row one by one, summing in another
  // order (the last bits of a score differ): the crop reaches this many cells further right, so
  // that the windows it filters one by one are, with Windows::every, all-zero ones or the whole
  // level's last ones; with centred_on_the_varied_area they are among the windows centred 3 to 10
  // cells right of the varied area, scored too (their scores may differ from dlib's in the last
  // bits).
  static constexpr long kTailCells = 7;
  dlib::frontal_face_detector detector_;
  Windows windows_;
};

}  // namespace FACETOOL_DETECTOR_CODE
}  // namespace facetool
