// Framings in photo alignment: the template at a framing, synth's projection agreeing with it,
// and the ring-mean fill (and mask cut) of crops reaching beyond the photo, against plain loops.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "libs/face/face_alignment.h"
#include "libs/face/face_crops.h"
#include "libs/face/face_mask.h"
#include "libs/face/face_template.h"
#include "libs/image/border_fill.h"
#include "libs/synth/landmark_projection.h"
#include "core/util/math_constants.h"
#include "tests/support/test_support.h"

namespace facetool {
namespace {

TEST(Framing, TemplateIsV1sTableMappedByTheFraming) {
  const Landmarks68& units = canonical_template_units();
  const CropFraming v2 = v2_framing();
  const Landmarks68 t1 = canonical_template(64), t2 = canonical_template(96, v2);
  for (int i = 0; i < kLandmarkCount; ++i) {
    EXPECT_EQ(t1[i].x, units[i].x * 64 - 0.5);  // v1: bit for bit the table
    EXPECT_NEAR(t2[i].x, (0.5 + v2.zoom * (units[i].x - v2.centre_x)) * 96 - 0.5, 1e-9);
    EXPECT_NEAR(t2[i].y, (0.5 + v2.zoom * (units[i].y - v2.centre_y)) * 96 - 0.5, 1e-9);
  }
  // v2 as documented: brows (top of 19 and 24) at about 0.15, chin (8) at about 0.85.
  EXPECT_NEAR(v2.to_y(std::min(units[19].y, units[24].y)), 0.146, 0.01);
  EXPECT_NEAR(v2.to_y(units[8].y), 0.854, 0.01);
}

TEST(Framing, AlignmentAtAFramingRecoversTheFaceTransform) {
  const int size = 96;
  const CropFraming v2 = v2_framing();
  const Similarity2 truth = Similarity2::from(0.8, 15 * kPi / 180, 12, -7);  // photo -> crop
  Landmarks68 photo_points = canonical_template(size, v2);
  for (Point2& p : photo_points) p = truth.inverse().apply(p);
  const FaceAlignment a = align_face(photo_points, size, v2);
  EXPECT_NEAR(a.photo_to_crop.a, truth.a, 1e-9);
  EXPECT_NEAR(a.photo_to_crop.b, truth.b, 1e-9);
  EXPECT_NEAR(a.photo_to_crop.tx, truth.tx, 1e-7);
  EXPECT_NEAR(a.photo_to_crop.ty, truth.ty, 1e-7);
}

// The contract between synth and alignment: the face model's landmarks through synth's camera at
// a framing land where alignment puts a face's landmarks at that framing.
TEST(Framing, SynthProjectionAgreesWithTheAlignmentTemplate) {
  const std::string model = std::string(FACETOOL_SHARED_DIR) + "/assets/ict-facekit/FaceXModel";
  if (!std::filesystem::exists(model + "/vertex_indices.json"))
    GTEST_SKIP() << "ICT face model not found at " << model;
  for (const CropFraming& framing : {v1_framing(), v2_framing(), parse_framing("zoom 1.3 centre 0.45 0.52 border edge-repeat", "test")}) {
    const std::vector<std::array<double, 2>> synth = project_neutral_landmarks(model, 22.5, framing);
    const int size = 128;
    const Landmarks68 aligned = canonical_template(size, framing);
    double worst = 0;
    for (int i = 0; i < kLandmarkCount; ++i) {
      worst = std::max(worst, std::abs(synth[i][0] * size - 0.5 - aligned[i].x));
      worst = std::max(worst, std::abs(synth[i][1] * size - 0.5 - aligned[i].y));
    }
    // The committed table has 6 decimals: 128 x 8 x 0.5e-6 crop pixels at most.
    EXPECT_LT(worst, 1e-3) << framing_text(framing);
  }
}

// A 40 x 30 photo shrunk by 2 into a 32 x 32 crop, placed so the crop reaches beyond its left,
// top and right edges.
struct BeyondThePhoto {
  RgbImage photo;
  Similarity2 photo_to_crop = Similarity2::from(0.5, 0.0, 2.25, 9.25);
  BeyondThePhoto() {
    photo.width = 40;
    photo.height = 30;
    photo.pixels = testing::random_values(40 * 30 * 3, 5, 0.0f, 1.0f);
  }
};

TEST(Framing, RingMeanFillMatchesPlainLoopsAndKeepsInsidePixels) {
  const BeyondThePhoto t;
  const int s = 32;
  std::vector<float> coverage, coverage_edge;
  const std::vector<float> edge = warp_to_crop(t.photo, t.photo_to_crop, s, BorderFill::kEdgeRepeat, &coverage_edge);
  const std::vector<float> ring = warp_to_crop(t.photo, t.photo_to_crop, s, BorderFill::kRingMean, &coverage);
  EXPECT_EQ(coverage, coverage_edge);
  EXPECT_EQ(edge, warp_to_crop(t.photo, t.photo_to_crop, s));  // the default is v1's edge repeat
  // Coverage by the footprint: crop pixel (x, y) spans photo [2x - 4.5 - 1, 2x - 4.5 + 1] etc.;
  // the photo spans [-0.5, 39.5] x [-0.5, 29.5].
  const size_t plane = static_cast<size_t>(s) * s;
  int full = 0, empty = 0;
  for (int y = 0; y < s; ++y)
    for (int x = 0; x < s; ++x) {
      const double cx = (x - 2.25) / 0.5, cy = (y - 9.25) / 0.5;  // footprint centre in the photo
      auto overlap = [](double lo, double hi, double a, double b) { return std::max(0.0, std::min(hi, b) - std::max(lo, a)); };
      const double area = overlap(cx - 1, cx + 1, -0.5, 39.5) * overlap(cy - 1, cy + 1, -0.5, 29.5) / 4;
      EXPECT_NEAR(coverage[y * s + x], area, 1e-6) << x << "," << y;
      full += area == 1;
      empty += area == 0;
    }
  ASSERT_GT(full, 100);
  ASSERT_GT(empty, 100);
  // Plain ring: fully covered pixels within border_ring_width(32) = 1 pixel of a pixel that is not.
  double sum[3] = {0, 0, 0};
  int count = 0;
  for (int y = 0; y < s; ++y)
    for (int x = 0; x < s; ++x) {
      if (coverage[y * s + x] < 1) continue;
      bool near = false;
      for (int j = std::max(0, y - 1); j <= std::min(s - 1, y + 1); ++j)
        for (int i = std::max(0, x - 1); i <= std::min(s - 1, x + 1); ++i) near = near || coverage[j * s + i] < 1;
      if (!near) continue;
      for (int k = 0; k < 3; ++k) sum[k] += edge[k * plane + y * s + x];
      ++count;
    }
  ASSERT_GT(count, 20);
  for (size_t p = 0; p < plane; ++p)
    for (int k = 0; k < 3; ++k) {
      if (coverage[p] == 1) {
        EXPECT_EQ(ring[k * plane + p], edge[k * plane + p]);
      }
      if (coverage[p] == 0) {
        EXPECT_NEAR(ring[k * plane + p], sum[k] / count, 1e-5);
      }
    }
}

TEST(Framing, RingMeanCropCutsTheMaskWhereTheCropLeavesThePhoto) {
  RgbImage photo;
  photo.width = 60;
  photo.height = 60;
  photo.pixels.assign(60 * 60 * 3, 0.4f);
  // A face whose chin reaches past the photo's bottom edge: the v2 template, large, low down.
  DetectedFace face;
  const Similarity2 place = Similarity2::from(1.2, 0.0, 0.0, 20.0);  // crop -> photo
  face.landmarks = canonical_template(64, v2_framing());
  for (Point2& p : face.landmarks) p = place.apply(p);
  const FaceCrop v2 = crop_face(photo, face, 64, false, v2_framing());
  const std::vector<float> whole = rasterize_mask(v2.mask_polygon, 64);
  int cut = 0;
  for (size_t p = 0; p < v2.mask.size(); ++p) {
    EXPECT_EQ(v2.mask[p], v2.inside[p] < 0.5f ? 0.0f : whole[p]) << "pixel " << p;
    cut += v2.inside[p] < 0.5f && whole[p] > 0;
  }
  // v1's framing (edge repeat) keeps the whole polygon.
  const FaceCrop v1 = crop_face(photo, face, 64, false);
  EXPECT_EQ(v1.mask, rasterize_mask(v1.mask_polygon, 64));
  EXPECT_GT(cut, 10) << "the chin should be cut by the photo's edge";
  // Outside the photo a constant photo stays that constant (the ring's mean), not 0 or streaks.
  for (size_t p = 0; p < v2.inside.size(); ++p) EXPECT_NEAR(v2.rgb[p], 0.4f, 1e-6);
}

}  // namespace
}  // namespace facetool
