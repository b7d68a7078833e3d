// The CNN face detector run by facetool's convolutions against dlib's own forward pass (the
// reference): the same boxes and the same scores to float rounding, on the example photos at
// several scales, with a low threshold so that many boxes reach the non-maximum suppression.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "libs/face/cnn_face_detector.h"
#include "libs/face/photo_reader.h"
#include "libs/io/image_io.h"

namespace facetool {
namespace {

// The photo scaled by `factor` (nearest pixel) as 8-bit sRGB, as the detector gives the CNN.
Srgb8Image srgb8(const RgbImage& photo, double factor) {
  Srgb8Image image;
  image.width = std::max(1, static_cast<int>(photo.width * factor));
  image.height = std::max(1, static_cast<int>(photo.height * factor));
  image.rgb.resize(static_cast<size_t>(image.width) * image.height * 3);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const int sx = std::min(photo.width - 1, static_cast<int>(x / factor));
      const int sy = std::min(photo.height - 1, static_cast<int>(y / factor));
      for (int c = 0; c < 3; ++c)
        image.rgb[(static_cast<size_t>(y) * image.width + x) * 3 + c] =
            linear_to_srgb8(photo.pixels[(static_cast<size_t>(sy) * photo.width + sx) * 3 + c]);
    }
  return image;
}

TEST(CnnForward, FacetoolsConvolutionsFindDlibsBoxesWithItsScores) {
  if (!std::filesystem::exists(kDefaultCnnFaceModel))
    GTEST_SKIP() << "needs dlib's CNN model " << kDefaultCnnFaceModel
                 << " (scripts/install-dependencies.sh)";
  CnnFaceDetector facetool_forward, dlib_forward;
  dlib_forward.set_forward(CnnForward::dlib);
  // Scores come through seven layers of float sums summed in another order: 1e-4 allows for
  // that rounding (the measured differences are below 1e-6), far below the scores' spread.
  const double score_tolerance = 1e-4;
  // Boxes scoring within this of the threshold may fall on either side of it by rounding.
  const double threshold = -1.2, margin = 0.01;
  size_t compared = 0;
  for (const char* name : {"grace_hopper_512x512.jpg", "astronaut.png"}) {
    const RgbImage photo = read_photo(std::string(FACETOOL_EXAMPLES_DIR) + "/photos/" + name);
    for (double factor : {0.37, 0.61, 1.0}) {
      const Srgb8Image image = srgb8(photo, factor);
      const std::vector<ScoredBox> ours = facetool_forward.detect(image, threshold);
      const std::vector<ScoredBox> theirs = dlib_forward.detect(image, threshold);
      SCOPED_TRACE(std::string(name) + " scaled by " + std::to_string(factor));
      for (const auto* pair : {&ours, &theirs}) {
        const std::vector<ScoredBox>& from = *pair;
        const std::vector<ScoredBox>& in = pair == &ours ? theirs : ours;
        for (const ScoredBox& b : from) {
          if (b.score < threshold + margin) continue;
          bool matched = false;
          for (const ScoredBox& o : in)
            if (o.left == b.left && o.top == b.top && o.right == b.right && o.bottom == b.bottom) {
              EXPECT_NEAR(o.score, b.score, score_tolerance);
              matched = true;
            }
          EXPECT_TRUE(matched) << "box (" << b.left << ", " << b.top << ", " << b.right << ", "
                               << b.bottom << ") score " << b.score << " found by "
                               << (pair == &ours ? "facetool" : "dlib") << " only";
          ++compared;
        }
      }
    }
  }
  EXPECT_GE(compared, 100u);  // 79 boxes a side at this threshold: faces and many false ones
}

}  // namespace
}  // namespace facetool
