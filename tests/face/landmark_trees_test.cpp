// LandmarkTrees (the landmark model run from its arrays: dlib's file parsed, or the build's copy
// mapped) against dlib::shape_predictor itself: the same 68 points, bit for bit, on real photos
// in many boxes and on random models.
#include <gtest/gtest.h>

#include <dlib/image_processing.h>
#include <dlib/image_processing/frontal_face_detector.h>
#include <dlib/image_transforms.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "libs/face/face_detector.h"
#include "libs/face/landmark_model_copy.h"
#include "libs/face/landmark_model_dlib.h"
#include "libs/face/landmark_trees.h"
#include "libs/io/image_io.h"

namespace facetool {
namespace {

using portable::LandmarkTrees;

dlib::array2d<unsigned char> grey_of(const RgbImage& photo) {
  dlib::array2d<unsigned char> grey(photo.height, photo.width);
  for (int y = 0; y < photo.height; ++y)
    for (int x = 0; x < photo.width; ++x) {
      const float* p = photo.at(x, y);
      grey[y][x] = linear_to_srgb8(luminance(p[0], p[1], p[2]));
    }
  return grey;
}

// Every part of both shapes, exactly; the number of differing parts.
int differing_parts(const dlib::full_object_detection& a, const dlib::full_object_detection& b) {
  EXPECT_EQ(a.num_parts(), b.num_parts());
  EXPECT_EQ(a.get_rect(), b.get_rect());
  int differ = 0;
  for (unsigned long i = 0; i < std::min(a.num_parts(), b.num_parts()); ++i) differ += a.part(i) != b.part(i);
  return differ;
}

// Boxes over `grey`: the face's box, moved and scaled around it, partly outside the photo, and
// random ones.
std::vector<dlib::rectangle> boxes_over(const dlib::array2d<unsigned char>& grey, const dlib::rectangle& face,
                                        std::mt19937& rng) {
  const long w = grey.nc(), h = grey.nr();
  std::vector<dlib::rectangle> boxes = {face};
  std::uniform_real_distribution<double> shift(-0.3, 0.3), scale(0.6, 1.6), unit(0, 1);
  for (int k = 0; k < 24; ++k) {
    const double s = scale(rng);
    const dlib::point centre(face.left() + face.width() / 2 + std::lround(shift(rng) * face.width()),
                             face.top() + face.height() / 2 + std::lround(shift(rng) * face.height()));
    boxes.push_back(dlib::centered_rect(centre, std::lround(s * face.width()), std::lround(s * face.height())));
  }
  boxes.push_back(dlib::rectangle(-w / 4, -h / 4, w / 2, h / 2));           // reaching out of the photo
  boxes.push_back(dlib::rectangle(w / 2, h / 2, w + w / 3, h + h / 3));
  for (int k = 0; k < 8; ++k) {
    const long x = std::lround(unit(rng) * w), y = std::lround(unit(rng) * h), side = 8 + std::lround(unit(rng) * w / 2);
    boxes.push_back(dlib::rectangle(x - side / 2, y - side / 2, x + side / 2, y + side / 2));
  }
  return boxes;
}

TEST(LandmarkTrees, TheStockModelGivesDlibsPointsOnRealPhotos) {
  if (!std::filesystem::exists(kDefaultLandmarkModel)) GTEST_SKIP() << kDefaultLandmarkModel << " not installed";
  dlib::shape_predictor dlibs;
  dlib::deserialize(kDefaultLandmarkModel) >> dlibs;
  std::ifstream in(kDefaultLandmarkModel, std::ios::binary);
  const LandmarkTrees trees(portable::landmark_model_copy_of(in));  // dlib's file parsed
  ASSERT_EQ(trees.num_parts(), 68u);
  // And the build's copy of it, mapped, as the detector uses it.
  std::optional<MappedLandmarkModel> mapped = map_landmark_model_copy(landmark_model_copy_path(), kDefaultLandmarkModel);
  ASSERT_TRUE(mapped.has_value()) << "no usable share/facetool/dlib/shape_predictor_68_face_landmarks.copy (rebuild)";
  const LandmarkTrees mapped_trees(std::move(*mapped));

  std::vector<std::string> photos = {std::string(FACETOOL_EXAMPLES_DIR) + "/photos/grace_hopper_512x512.jpg",
                                     std::string(FACETOOL_EXAMPLES_DIR) + "/photos/astronaut.png"};
  const std::filesystem::path utk = std::filesystem::path(FACETOOL_SHARED_DIR) / "assets/faces/utkface-crop-part1";
  if (std::filesystem::is_directory(utk)) {  // every 1,000th photo of the sorted list
    std::vector<std::string> all;
    for (const auto& entry : std::filesystem::directory_iterator(utk)) all.push_back(entry.path().string());
    std::sort(all.begin(), all.end());
    for (size_t i = 0; i < all.size(); i += 1000) photos.push_back(all[i]);
  }
  dlib::frontal_face_detector hog = dlib::get_frontal_face_detector();
  std::mt19937 rng(11);
  int shapes = 0;
  for (const std::string& path : photos) {
    const dlib::array2d<unsigned char> grey = grey_of(read_rgb_image(path, true));
    dlib::array2d<unsigned char> mirrored;
    dlib::flip_image_left_right(grey, mirrored);
    // The face found by dlib's HOG detector (else the middle of the photo), and its mirror image.
    const long w = grey.nc(), h = grey.nr();
    const std::vector<dlib::rectangle> found = hog(grey);
    const dlib::rectangle face = found.empty() ? dlib::centered_rect(dlib::point(w / 2, h / 2), w / 2, h / 2) : found[0];
    const dlib::rectangle mirrored_face(w - 1 - face.right(), face.top(), w - 1 - face.left(), face.bottom());
    auto compare_in = [&](const dlib::array2d<unsigned char>& image, const dlib::rectangle& box_of_face) {
      for (const dlib::rectangle& box : boxes_over(image, box_of_face, rng)) {
        const dlib::full_object_detection reference = dlibs(image, box);
        EXPECT_EQ(differing_parts(trees(image, box), reference), 0) << path << " box " << box;
        EXPECT_EQ(differing_parts(mapped_trees(image, box), reference), 0) << "mapped copy, " << path << " box " << box;
        ++shapes;
      }
    };
    compare_in(grey, face);
    compare_in(mirrored, mirrored_face);
  }
  EXPECT_GE(shapes, 2 * 2 * 35);
  std::printf("%d shapes on %zu photos, each the same as dlib's\n", shapes, photos.size());
}

// A random model (3 parts, 3 levels of 6 trees of depth 3) against dlib's predictor built from it.
LandmarkModelCopy random_model(std::mt19937& rng) {
  std::uniform_real_distribution<float> shape(0.2f, 0.8f), around(-0.3f, 1.3f), thresh(-60, 60), leaf(-0.05f, 0.05f);
  LandmarkModelCopy c;
  c.parts = 3, c.cascades = 3, c.trees = 6, c.splits = 7, c.pixels = 9;
  for (uint32_t i = 0; i < 2 * c.parts; ++i) c.initial_shape.push_back(shape(rng));
  for (uint32_t i = 0; i < 2 * c.cascades * c.pixels; ++i) c.pixel_coordinates.push_back(around(rng));
  for (uint32_t i = 0; i < 2 * c.cascades * c.trees * c.splits; ++i) c.split_pixels.push_back(rng() % c.pixels);
  for (uint32_t i = 0; i < c.cascades * c.trees * c.splits; ++i) c.split_thresholds.push_back(thresh(rng));
  for (uint32_t i = 0; i < c.cascades * c.trees * c.leaves() * 2 * c.parts; ++i) c.leaf_values.push_back(leaf(rng));
  return c;
}

TEST(LandmarkTrees, RandomModelsGiveDlibsPointsOnNoise) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> byte(0, 255);
  dlib::array2d<unsigned char> image(61, 83);
  for (long y = 0; y < image.nr(); ++y)
    for (long x = 0; x < image.nc(); ++x) image[y][x] = static_cast<unsigned char>((x * 7 + y * 3) % 97 + byte(rng) / 3);
  int moved = 0;
  for (int m = 0; m < 20; ++m) {
    const LandmarkModelCopy model = random_model(rng);
    ASSERT_TRUE(model.consistent());
    const dlib::shape_predictor dlibs = portable::shape_predictor_from_copy(model);
    const LandmarkTrees trees(model);
    for (const dlib::rectangle& box : {dlib::rectangle(10, 8, 50, 48), dlib::rectangle(-20, -5, 30, 40),
                                       dlib::rectangle(40, 20, 100, 80), dlib::rectangle(0, 0, 82, 60)}) {
      const dlib::full_object_detection ours = trees(image, box), reference = dlibs(image, box);
      EXPECT_EQ(differing_parts(ours, reference), 0) << "model " << m << " box " << box;
      // The trees moved the shape away from the mean (the test sees the leaves' effect).
      const dlib::point mean = dlib::impl::unnormalizing_tform(box)(dlib::vector<float, 2>(model.initial_shape[0], model.initial_shape[1]));
      moved += ours.part(0) != mean;
    }
  }
  EXPECT_GT(moved, 40);
}

}  // namespace
}  // namespace facetool
