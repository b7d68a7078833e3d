// Guided paste-back against bilinear on a sharp edge the crop cannot hold, and its contract: the
// blend by alpha, unit normals, a smooth map under a flat guide, and the face's guide.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "libs/face/face_alignment.h"
#include "libs/face/guided_paste.h"
#include "libs/face/paste_back.h"

namespace facetool {
namespace {

// A 96 x 96 photo with a vertical edge between columns 49 and 50 (0.1 left, 0.9 right), a 24 x 24
// crop of it at 4 photo pixels per crop pixel (area averaged, so the crop column over photo
// columns 48..51 is 0.5: the edge blurred), and a square mask over most of the crop.
struct EdgeCase {
  RgbImage photo;
  Similarity2 photo_to_crop = Similarity2::from(0.25, 0.0, -0.375, -0.375);
  std::vector<float> crop;
  PasteRegion region;
  static float truth(int x) { return x <= 49 ? 0.1f : 0.9f; }
  EdgeCase() {
    photo.width = photo.height = 96;
    photo.pixels.resize(96 * 96 * 3);
    for (int y = 0; y < 96; ++y)
      for (int x = 0; x < 96; ++x)
        for (int k = 0; k < 3; ++k) photo.at(x, y)[k] = truth(x);
    crop = warp_to_crop(photo, photo_to_crop, 24);
    const std::vector<Point2> square = {{2, 2}, {21, 2}, {21, 21}, {2, 21}};
    region = paste_region(96, 96, photo_to_crop, 24, square, 0.0);
  }
};

// Along row 48: the pixels whose value lies strictly between 10 % and 90 % of the step (the
// edge's width in photo pixels), and the mean |value - truth| within 8 pixels of the edge.
struct EdgeMeasure {
  int width = 0;
  double error = 0;
};
EdgeMeasure measure(const std::vector<float>& planar) {
  EdgeMeasure m;
  const int y = 48;
  for (int x = 20; x < 76; ++x) {
    const float v = planar[y * 96 + x];
    m.width += v > 0.1f + 0.08f && v < 0.9f - 0.08f;
  }
  for (int x = 42; x < 58; ++x) m.error += std::abs(planar[y * 96 + x] - EdgeCase::truth(x)) / 16;
  return m;
}

TEST(GuidedPaste, SharpensAnEdgeTheCropBlurredBeyondBilinear) {
  const EdgeCase t;
  std::vector<float> bilinear(3 * 96 * 96, 0.0f), guided(3 * 96 * 96, 0.0f);
  paste_channels(t.region, t.crop.data(), 3, bilinear.data(), 96, 96);
  paste_channels_guided(t.region, t.crop.data(), 3, face_guide(t.photo, t.region), guided.data(), 96, 96, false,
                        0.0f, 1.0f);
  const EdgeMeasure b = measure(bilinear), g = measure(guided);
  std::printf("edge width (10-90 %%): bilinear %d px, guided %d px; mean |error| near the edge: bilinear %.4f, guided %.4f\n",
              b.width, g.width, b.error, g.error);
  EXPECT_GE(b.width, 4);
  EXPECT_LE(g.width * 2, b.width);
  EXPECT_LT(g.error * 2, b.error);
}

TEST(GuidedPaste, FlatGuideGivesSmoothValuesUnitNormalsAndKeepsOutsideAlone) {
  const EdgeCase t;
  RgbImage flat = t.photo;
  std::fill(flat.pixels.begin(), flat.pixels.end(), 0.5f);
  // A field of normals tilting across the crop.
  std::vector<float> normals(3 * 24 * 24);
  for (int p = 0; p < 24 * 24; ++p) {
    const double angle = 0.05 * (p % 24) - 0.6;
    normals[p] = static_cast<float>(std::sin(angle));
    normals[24 * 24 + p] = 0.0f;
    normals[2 * 24 * 24 + p] = static_cast<float>(std::cos(angle));
  }
  std::vector<float> out(3 * 96 * 96, 7.0f);
  paste_channels_guided(t.region, normals.data(), 3, face_guide(flat, t.region), out.data(), 96, 96, true, 0, 0);
  std::vector<float> bilinear(3 * 96 * 96, 7.0f);
  paste_channels(t.region, normals.data(), 3, bilinear.data(), 96, 96);
  int inside = 0;
  for (int p = 0; p < 96 * 96; ++p) {
    const int x = p % 96, y = p / 96;
    const bool in = x >= t.region.x0 && x < t.region.x0 + t.region.width && y >= t.region.y0 &&
                    y < t.region.y0 + t.region.height &&
                    t.region.alpha[(y - t.region.y0) * t.region.width + (x - t.region.x0)] > 0;
    if (!in) {
      EXPECT_EQ(out[p], 7.0f);
      continue;
    }
    ++inside;
    const double n = std::sqrt(out[p] * out[p] + out[96 * 96 + p] * out[96 * 96 + p] +
                               out[2 * 96 * 96 + p] * out[2 * 96 * 96 + p]);
    EXPECT_NEAR(n, 1.0, 1e-5);
    // A smooth field and a flat guide: a = 0 and b is the twice box-averaged field, which for a
    // nearly linear field away from the crop's edges is the field: guided equals bilinear there.
    if (x > 20 && x < 76) {
      EXPECT_NEAR(out[p], bilinear[p], 0.01) << x << "," << y;
    }
  }
  EXPECT_GT(inside, 5000);
}

float luma(const float* p) {
  return 0.2126f * linear_to_srgb(p[0]) + 0.7152f * linear_to_srgb(p[1]) + 0.0722f * linear_to_srgb(p[2]);
}

// face_guide reads only the face's part of the photo but gives, there, the luma of the
// sRGB-encoded photo, and in the crop what warping the whole photo's luma does.
TEST(GuidedPaste, FaceGuideIsThePhotosLumaAndItsWarp) {
  RgbImage photo;
  photo.width = 70;
  photo.height = 50;
  photo.pixels.resize(70 * 50 * 3);
  for (size_t i = 0; i < photo.pixels.size(); ++i) photo.pixels[i] = static_cast<float>((i * 7919) % 101) / 100.0f;
  RgbImage grey = photo;
  for (int y = 0; y < 50; ++y)
    for (int x = 0; x < 70; ++x) std::fill_n(grey.at(x, y), 3, std::clamp(luma(photo.at(x, y)), 0.0f, 1.0f));
  const std::vector<Point2> square = {{2, 2}, {13, 2}, {13, 13}, {2, 13}};
  for (const Similarity2& t : {Similarity2::from(0.5, 0.3, -3.0, 2.0), Similarity2::from(0.2, -0.1, 4.0, 5.0),
                               Similarity2::from(0.35, 1.2, 8.0, -10.0)}) {
    const PasteRegion region = paste_region(70, 50, t, 16, square, 1.0);
    const FaceGuide g = face_guide(photo, region);
    ASSERT_GT(g.width * g.height, 0);
    EXPECT_LE(g.x0, region.x0);
    EXPECT_GE(g.x0 + g.width, region.x0 + region.width);
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x)
        EXPECT_EQ(g.photo[y * g.width + x], grey.at(g.x0 + x, g.y0 + y)[0]);
    std::vector<float> whole = warp_to_crop(grey, t, 16);
    whole.resize(16 * 16);
    ASSERT_EQ(g.crop.size(), whole.size());
    for (size_t i = 0; i < whole.size(); ++i) EXPECT_NEAR(g.crop[i], whole[i], 1e-5) << "pixel " << i;
  }
}

}  // namespace
}  // namespace facetool
