// HogScan, the HOG search around the photo only, gives dlib's own detector's boxes, scores and
// order, box for box, on padded photos: a face in the middle, cut by the photo's edge, small
// (found at the finest levels only), large (at the coarsest only), in a turned photo (black
// corners) and unpadded, with the detector over all levels and over one octave; searching only
// windows centred on the photo (the detector's search), it finds the same faces.
#include <gtest/gtest.h>

#include <dlib/image_io.h>
#include <dlib/image_processing.h>
#include <dlib/image_processing/frontal_face_detector.h>
#include <dlib/image_transforms.h>

#include <cstdio>
#include <string>
#include <vector>

#include "libs/face/hog_scan.h"

namespace facetool {
namespace {

using Grey = dlib::array2d<unsigned char>;
using portable::HogScan;
using portable::one_octave;
using portable::varied_area;

Grey example_grey() {
  Grey grey;
  dlib::load_image(grey, std::string(FACETOOL_EXAMPLES_DIR) + "/photos/grace_hopper_512x512.jpg");
  return grey;
}

// `image` on a flat grey (its mean) grown by `pad` pixels on every side, as the detector pads.
Grey padded(const Grey& image, long pad) {
  double sum = 0;
  for (long y = 0; y < image.nr(); ++y)
    for (long x = 0; x < image.nc(); ++x) sum += image[y][x];
  Grey out(image.nr() + 2 * pad, image.nc() + 2 * pad);
  dlib::assign_all_pixels(out, static_cast<unsigned char>(sum / static_cast<double>(image.size()) + 0.5));
  for (long y = 0; y < image.nr(); ++y)
    for (long x = 0; x < image.nc(); ++x) out[y + pad][x + pad] = image[y][x];
  return out;
}

Grey part(const Grey& image, long left, long top, long width, long height) {
  Grey out(height, width);
  for (long y = 0; y < height; ++y)
    for (long x = 0; x < width; ++x) out[y][x] = image[top + y][left + x];
  return out;
}

Grey scaled(const Grey& image, double scale) {
  Grey out(std::lround(image.nr() * scale), std::lround(image.nc() * scale));
  dlib::resize_image(image, out, dlib::interpolate_bilinear());
  return out;
}

// dlib's boxes and HogScan's on `image` at `threshold`, the same in number and box for box;
// returns how many boxes reach 0.25 (the default minimum score).
size_t expect_same(dlib::frontal_face_detector& detector, const Grey& image, double threshold, const char* what,
                   HogScan::Windows windows = HogScan::Windows::every) {
  std::vector<dlib::rect_detection> dlibs, ours;
  detector(image, dlibs, threshold);
  HogScan scan(detector, windows);
  scan(image, ours, threshold);
  EXPECT_EQ(ours.size(), dlibs.size()) << what << " at " << threshold;
  for (size_t i = 0; i < std::min(ours.size(), dlibs.size()); ++i) {
    EXPECT_EQ(ours[i].rect, dlibs[i].rect) << what << " box " << i;
    EXPECT_EQ(ours[i].detection_confidence, dlibs[i].detection_confidence) << what << " box " << i;
    EXPECT_EQ(ours[i].weight_index, dlibs[i].weight_index) << what << " box " << i;
  }
  size_t faces = 0;
  for (const dlib::rect_detection& d : dlibs) faces += d.detection_confidence >= 0.25;
  std::printf("%s (%ld x %ld) at %.2f: %zu boxes, %zu of at least 0.25\n", what, image.nc(), image.nr(),
              threshold, dlibs.size(), faces);
  return faces;
}

TEST(HogScan, VariedAreaIsWhereTheImageIsNotItsCornersGrey) {
  Grey image(40, 50);
  dlib::assign_all_pixels(image, 7);
  EXPECT_TRUE(varied_area(image).is_empty());
  image[12][30] = 8;
  EXPECT_EQ(varied_area(image), dlib::rectangle(30, 12, 30, 12));
  image[20][3] = 0;
  image[39][45] = 255;
  EXPECT_EQ(varied_area(image), dlib::rectangle(3, 12, 45, 39));
  image[0][49] = 1;
  EXPECT_EQ(varied_area(image), dlib::rectangle(3, 0, 49, 39));
}

TEST(HogScan, SameBoxesAsDlibsOwnSearch) {
  const Grey photo = example_grey();
  ASSERT_EQ(photo.nc(), 512);
  dlib::frontal_face_detector all_levels = dlib::get_frontal_face_detector();
  dlib::frontal_face_detector octave = one_octave(all_levels);
  // The face (about 180 pixels, around (260, 190)) in the middle, cut by the left and the top
  // edge (a third of it outside), small, large, turned, and the photo unpadded.
  const Grey middle = padded(photo, 128);
  const Grey cut_left = padded(part(photo, 200, 0, 312, 512), 78);
  const Grey cut_top = padded(part(photo, 0, 130, 512, 382), 95);
  const Grey small = scaled(padded(scaled(photo, 0.3), 38), 2.0);  // a 54-pixel face, enlarged
  const Grey small_cut = scaled(padded(scaled(part(photo, 210, 0, 302, 512), 0.3), 23), 2.0);
  const Grey large = padded(scaled(photo, 1.8), 230);               // found at coarse levels only
  Grey turned;
  dlib::rotate_image(middle, turned, 0.5, dlib::interpolate_bilinear());
  for (double threshold : {0.25, -1.0, -3.0}) {
    EXPECT_GE(expect_same(all_levels, middle, threshold, "in the middle"), 1u);
    EXPECT_GE(expect_same(octave, middle, threshold, "in the middle, one octave"), 0u);
    EXPECT_GE(expect_same(all_levels, cut_left, threshold, "cut by the left edge"), 1u);
    EXPECT_GE(expect_same(all_levels, cut_top, threshold, "cut by the top edge"), 1u);
    EXPECT_GE(expect_same(octave, small, threshold, "small, one octave"), 1u);
    EXPECT_GE(expect_same(octave, small_cut, threshold, "small and cut, one octave"), 1u);
    EXPECT_GE(expect_same(all_levels, large, threshold, "large"), 1u);
    expect_same(all_levels, turned, threshold, "turned");
    expect_same(all_levels, photo, threshold, "unpadded");
  }
}

// The detector's search, of windows centred on the photo only, finds dlib's faces (score 0.25
// and more), box for box: in the middle, cut by the photo's edge (dlib finds the face cut by 17
// and 29 % on the left, not by 40 %; the faces of the test sets hang out by up to 22 %), small,
// large, turned, unpadded.
TEST(HogScan, WindowsCentredOnThePhotoFindEveryFace) {
  const Grey photo = example_grey();
  dlib::frontal_face_detector all_levels = dlib::get_frontal_face_detector();
  dlib::frontal_face_detector octave = one_octave(all_levels);
  const auto centred = HogScan::Windows::centred_on_the_varied_area;
  Grey turned;
  dlib::rotate_image(padded(photo, 128), turned, -0.5, dlib::interpolate_bilinear());
  EXPECT_EQ(expect_same(all_levels, padded(photo, 128), 0.25, "in the middle", centred), 1u);
  // The face spans x 164-374 and y 118-328: cut by 17, 29 and 40 % on the left, 25 % at the top
  // and 25 % on the right.
  for (long cut : {200, 225, 248}) {
    const Grey image = padded(part(photo, cut, 0, 512 - cut, 512), 128);
    EXPECT_EQ(expect_same(all_levels, image, 0.25, "cut by the left edge", centred),
              expect_same(all_levels, image, 0.25, "cut by the left edge", HogScan::Windows::every));
  }
  EXPECT_EQ(expect_same(all_levels, padded(part(photo, 0, 170, 512, 342), 85), 0.25, "cut at the top", centred), 1u);
  EXPECT_EQ(expect_same(all_levels, padded(part(photo, 0, 0, 322, 512), 80), 0.25, "cut on the right", centred), 1u);
  EXPECT_EQ(expect_same(octave, scaled(padded(scaled(photo, 0.3), 38), 2.0), 0.25, "small", centred), 1u);
  EXPECT_EQ(expect_same(octave, scaled(padded(scaled(part(photo, 210, 0, 302, 512), 0.3), 23), 2.0), 0.25,
                        "small and cut", centred), 1u);
  EXPECT_EQ(expect_same(all_levels, padded(scaled(photo, 1.8), 230), 0.25, "large", centred), 1u);
  EXPECT_EQ(expect_same(all_levels, turned, 0.25, "turned", centred), 1u);
  EXPECT_EQ(expect_same(all_levels, photo, 0.25, "unpadded", centred), 1u);
}

// At a threshold where a window of zero features would be a face, HogScan leaves the search to
// dlib (windows of the padding would be boxes).
TEST(HogScan, AThresholdThatTakesFlatWindowsIsDlibsSearch) {
  dlib::frontal_face_detector all_levels = dlib::get_frontal_face_detector();
  double highest = -1e300;  // the best score of a zero window, over the filters
  for (unsigned long i = 0; i < all_levels.num_detectors(); ++i)
    highest = std::max(highest, -all_levels.get_w(i)(all_levels.get_scanner().get_num_dimensions()));
  std::printf("a zero window scores %.3f at best\n", highest);
  const Grey small = padded(scaled(example_grey(), 0.25), 64);
  expect_same(all_levels, small, highest + 1e-3, "just above a zero window's score");
  expect_same(all_levels, small, highest - 1e-3, "just below it");
  std::vector<dlib::rect_detection> found;
  HogScan scan(all_levels);
  scan(small, found, highest - 1e-3);
  EXPECT_GT(found.size(), 2u);  // the padding's windows too: dlib's search ran
}

}  // namespace
}  // namespace facetool
