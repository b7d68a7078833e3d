// Photo-pipeline geometry against closed forms and plain definitions: similarity fit, mask
// distance, template table, align-then-paste-back identity, contact-sheet resizing, and normals
// and light carried back from rotated photos.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "libs/face/face_alignment.h"
#include "libs/face/face_mask.h"
#include "libs/face/face_template.h"
#include "libs/face/frame_rotation.h"
#include "libs/face/landmark_drawing.h"
#include "libs/face/paste_back.h"
#include "libs/face/photo_reader.h"
#include "libs/synth/landmark_projection.h"
#include "core/sh/sh_eval.h"
#include "core/util/error.h"
#include "core/util/math_constants.h"

namespace facetool {
namespace {


TEST(SimilarityFit, RecoversAKnownTransformAndItsInverse) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-50, 50);
  const Similarity2 truth = Similarity2::from(1.7, 0.6, 12.5, -4.25);
  std::vector<Point2> from, to;
  for (int i = 0; i < 20; ++i) {
    from.push_back({u(rng), u(rng)});
    to.push_back(truth.apply(from.back()));
  }
  const Similarity2 fit = fit_similarity(from, to);
  EXPECT_NEAR(fit.a, truth.a, 1e-9);
  EXPECT_NEAR(fit.b, truth.b, 1e-9);
  EXPECT_NEAR(fit.tx, truth.tx, 1e-9);
  EXPECT_NEAR(fit.ty, truth.ty, 1e-9);
  const Similarity2 round = fit.inverse().then_after(fit);
  EXPECT_NEAR(round.a, 1, 1e-12);
  EXPECT_NEAR(round.b, 0, 1e-12);
  EXPECT_NEAR(round.tx, 0, 1e-9);
  EXPECT_NEAR(round.ty, 0, 1e-9);
}

TEST(SimilarityFit, RejectsDegenerateInput) {
  EXPECT_THROW(fit_similarity({{1, 1}, {1, 1}}, {{0, 0}, {1, 1}}), Error);
  EXPECT_THROW(fit_similarity({{1, 1}}, {{0, 0}}), Error);
}

TEST(FaceMask, SignedDistanceToASquare) {
  Landmarks68 points;
  for (int i = 0; i < kLandmarkCount; ++i) points[i] = {5.0, 5.0};  // inside, ignored by the hull
  points[0] = {0, 0};
  points[1] = {10, 0};
  points[2] = {10, 10};
  points[3] = {0, 10};
  const std::vector<Point2> hull = face_mask_polygon(points, false);
  ASSERT_EQ(hull.size(), 4u);
  EXPECT_NEAR(signed_distance_inside(hull, {5, 5}), 5, 1e-12);
  EXPECT_NEAR(signed_distance_inside(hull, {1, 5}), 1, 1e-12);
  EXPECT_NEAR(signed_distance_inside(hull, {-3, 5}), -3, 1e-12);
  EXPECT_NEAR(signed_distance_inside(hull, {13, 14}), -5, 1e-12);
  const std::vector<float> raster = rasterize_mask(hull, 12);
  double area = 0;
  for (float v : raster) area += v;
  EXPECT_EQ(area, 121);  // pixel centres 0..10 in both directions
}

TEST(FaceMask, ConvexInteriorAgreesWithTheSignedDistance) {
  std::mt19937 rng(11);
  std::normal_distribution<double> spread(0.0, 30.0);
  Landmarks68 points;
  for (Point2& p : points) p = {100 + spread(rng), 100 + 1.3 * spread(rng)};
  const std::vector<Point2> hull = face_mask_polygon(points, true);
  const ConvexInterior interior(hull);
  std::uniform_real_distribution<double> anywhere(-20.0, 220.0);
  int inside = 0;
  for (int i = 0; i < 5000; ++i) {
    const Point2 p{anywhere(rng), anywhere(rng)};
    const double reference = std::max(0.0, signed_distance_inside(hull, p));
    EXPECT_NEAR(interior.depth(p), reference, 1e-9) << p.x << ", " << p.y;
    EXPECT_EQ(interior.contains(p), signed_distance_inside(hull, p) >= 0) << p.x << ", " << p.y;
    inside += reference > 0;
  }
  EXPECT_GT(inside, 500);  // both sides of the boundary were tried
  EXPECT_LT(inside, 4500);
  EXPECT_EQ(ConvexInterior({{0, 0}, {1, 1}}).depth({0.5, 0.5}), 0.0);  // no interior
  EXPECT_FALSE(ConvexInterior({{0, 0}, {1, 1}}).contains({0.5, 0.5}));
}

// resize_to_width's plain definition: each output pixel the mean of n x n bilinear samples.
RgbImage resize_by_samples(const RgbImage& image, int width) {
  const double scale = static_cast<double>(width) / image.width;
  RgbImage out;
  out.width = width;
  out.height = std::max(1, static_cast<int>(std::lround(image.height * scale)));
  out.pixels.resize(static_cast<size_t>(out.width) * out.height * 3);
  const int n = std::clamp(static_cast<int>(std::ceil(1.0 / scale)), 1, 16);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      double sum[3] = {0, 0, 0};
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          float s[3];
          sample_rgb_bilinear(image, (x - 0.5 + (i + 0.5) / n) / scale, (y - 0.5 + (j + 0.5) / n) / scale, s);
          for (int c = 0; c < 3; ++c) sum[c] += s[c];
        }
      for (int c = 0; c < 3; ++c) out.at(x, y)[c] = static_cast<float>(sum[c] / (n * n));
    }
  return out;
}

TEST(ContactSheet, ResizeToWidthIsTheMeanOfBilinearSamples) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> value(0.0f, 1.0f);
  RgbImage image;
  image.width = 61;
  image.height = 47;
  image.pixels.resize(static_cast<size_t>(image.width) * image.height * 3);
  for (float& v : image.pixels) v = value(rng);
  for (int width : {1, 7, 13, 30, 61, 64, 65, 200}) {
    const RgbImage fast = resize_to_width(image, width), plain = resize_by_samples(image, width);
    ASSERT_EQ(fast.width, plain.width);
    ASSERT_EQ(fast.height, plain.height);
    double worst = 0;
    for (size_t k = 0; k < fast.pixels.size(); ++k)
      worst = std::max(worst, static_cast<double>(std::abs(fast.pixels[k] - plain.pixels[k])));
    EXPECT_LT(worst, 1e-5) << "width " << width;
  }
}

TEST(FaceMask, ForeheadExtensionOnlyAddsAboveTheBrows) {
  const Landmarks68 t = canonical_template(128);
  const std::vector<Point2> plain = face_mask_polygon(t, false), extended = face_mask_polygon(t, true);
  const std::vector<float> a = rasterize_mask(plain, 128), b = rasterize_mask(extended, 128);
  // The hull joins the lifted brows to the top of the jaw line (0 and 16, beside the eyes).
  const double jaw_top = std::max(t[0].y, t[16].y);
  int added = 0;
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x) {
      const size_t i = static_cast<size_t>(y) * 128 + x;
      EXPECT_GE(b[i], a[i]);
      if (b[i] > a[i]) {
        ++added;
        EXPECT_LT(y, jaw_top + 1) << "extension below the jaw line's top at " << x << "," << y;
      }
    }
  EXPECT_GT(added, 100);
}

TEST(FaceTemplate, CommittedTableIsWhatTheGeneratorGives) {
  const std::string model = std::string(FACETOOL_SHARED_DIR) + "/assets/ict-facekit/FaceXModel";
  if (!std::filesystem::exists(model + "/vertex_indices.json"))
    GTEST_SKIP() << "ICT face model not found at " << model;
  const std::vector<std::array<double, 2>> generated = project_neutral_landmarks(model);
  const Landmarks68& table = canonical_template_units();
  ASSERT_EQ(generated.size(), static_cast<size_t>(kLandmarkCount));
  for (int i = 0; i < kLandmarkCount; ++i) {
    EXPECT_NEAR(generated[i][0], table[i].x, 1e-6) << "landmark " << i;
    EXPECT_NEAR(generated[i][1], table[i].y, 1e-6) << "landmark " << i;
  }
  // Mirror symmetry of the neutral face: outer eye corners 36 and 45 level, centred.
  EXPECT_NEAR(table[36].y, table[45].y, 1e-3);
  EXPECT_NEAR(table[36].x + table[45].x, 1.0, 1e-3);
}

std::string example(const std::string& name) {
  return std::string(FACETOOL_EXAMPLES_DIR) + "/photos/" + name;
}

TEST(PasteBack, AlignThenPasteBackReproducesThePhotoInsideTheMask) {
  const RgbImage photo = read_photo(example("astronaut.png"));
  const int size = 256;
  // A face placed in the photo by a known similarity (rotated 20 degrees, scale ~1).
  const Similarity2 truth = Similarity2::from(1.05, 20 * kPi / 180, -40, 10);
  Landmarks68 landmarks = canonical_template(size);
  for (Point2& p : landmarks) p = truth.inverse().apply(p);
  const FaceAlignment a = align_face(landmarks, size);
  EXPECT_NEAR(a.photo_to_crop.a, truth.a, 1e-9);
  EXPECT_NEAR(a.photo_to_crop.b, truth.b, 1e-9);
  const std::vector<float> crop = warp_to_crop(photo, a.photo_to_crop, size);
  const std::vector<Point2> polygon = face_mask_polygon(a.crop_landmarks, true);
  const PasteRegion region = paste_region(photo.width, photo.height, a.photo_to_crop, size, polygon, 3.0);

  const size_t plane = static_cast<size_t>(photo.width) * photo.height;
  const std::vector<float> original = planar_from_rgb(photo);
  std::vector<float> pasted = original;
  paste_channels(region, crop.data(), 3, pasted.data(), photo.width, photo.height);

  double inside_error = 0;
  int inside = 0, outside_changed = 0;
  for (int y = 0; y < photo.height; ++y)
    for (int x = 0; x < photo.width; ++x) {
      float alpha = 0;
      if (x >= region.x0 && x < region.x0 + region.width && y >= region.y0 && y < region.y0 + region.height)
        alpha = region.alpha[static_cast<size_t>(y - region.y0) * region.width + (x - region.x0)];
      const size_t p = static_cast<size_t>(y) * photo.width + x;
      for (int c = 0; c < 3; ++c) {
        const float d = std::abs(pasted[c * plane + p] - original[c * plane + p]);
        if (alpha >= 1.0f) inside_error += d;
        if (alpha <= 0.0f && d != 0.0f) ++outside_changed;
      }
      if (alpha >= 1.0f) ++inside;
    }
  ASSERT_GT(inside, 5000);
  const double mean = inside_error / (3.0 * inside);
  std::printf("align + paste-back: mean |difference| inside the mask %.4f (linear), %d pixels\n",
              mean, inside);
  EXPECT_LT(mean, 0.015);  // two bilinear resamplings of a photo at about its own scale (0.0094 measured)
  EXPECT_EQ(outside_changed, 0);
}

// Pastes a crop-frame normal field back through `photo_to_crop` (rotated to the photo's frame).
std::vector<float> pasted_normals(const std::vector<float>& crop_normals, int size,
                                  const Similarity2& photo_to_crop, int w, int h, PasteRegion* region) {
  std::vector<float> n = crop_normals;
  rotate_normals_to_photo(n.data(), static_cast<size_t>(size) * size, photo_to_crop);
  const std::vector<Point2> square = {{8, 8}, {size - 9.0, 8}, {size - 9.0, size - 9.0}, {8, size - 9.0}};
  *region = paste_region(w, h, photo_to_crop, size, square, 2.0);
  std::vector<float> out(static_cast<size_t>(w) * h * 3, 0.0f);
  paste_channels(*region, n.data(), 3, out.data(), w, h);
  return out;
}

TEST(FrameRotation, UpInTheCropIsLeftInAPhotoTurnedCounterClockwise) {
  // A face whose head points left on screen (the photo turned 90 degrees counter-clockwise):
  // the crop's up (+Y) must come back as the photo's left (-X).
  const int size = 128;
  Landmarks68 landmarks = canonical_template(size);
  for (Point2& p : landmarks) p = {p.y + 100, 300 - p.x};  // screen CCW turn: (x, y) -> (y, -x)
  const FaceAlignment a = align_face(landmarks, size);
  std::vector<float> up = {0, 1, 0};
  rotate_normals_to_photo(up.data(), 1, a.photo_to_crop);
  EXPECT_NEAR(up[0], -1, 1e-9);
  EXPECT_NEAR(up[1], 0, 1e-9);
  EXPECT_NEAR(up[2], 0, 1e-9);
}

class RotatedPhoto : public ::testing::TestWithParam<double> {};

TEST_P(RotatedPhoto, NormalsAndLightPointTheSameWayInThePhotoFrame) {
  const double degrees = GetParam();  // counter-clockwise on screen
  const double t = degrees * kPi / 180;
  const int size = 64, w = 160, h = 160;
  // Any crop normal field that varies across the crop.
  std::vector<float> normals(3 * size * size);
  const size_t plane = static_cast<size_t>(size) * size;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const double nx = (x - 30.0) / 50, ny = (20.0 - y) / 60, nz = std::sqrt(1 - nx * nx - ny * ny);
      const size_t i = static_cast<size_t>(y) * size + x;
      normals[i] = static_cast<float>(nx);
      normals[plane + i] = static_cast<float>(ny);
      normals[2 * plane + i] = static_cast<float>(nz);
    }
  const Similarity2 upright = Similarity2::from(0.5, 0.2, 10, 5);
  // The turn on screen about the photo centre; CCW on screen is a negative angle in y-down pixels.
  const Similarity2 turn_about_origin = Similarity2::from(1, -t, 0, 0);
  const Point2 c{w / 2.0 - 0.5, h / 2.0 - 0.5}, tc = turn_about_origin.apply(c);
  const Similarity2 turn = Similarity2::from(1, -t, c.x - tc.x, c.y - tc.y);
  const Similarity2 rotated = upright.then_after(turn.inverse());
  PasteRegion ru, rr;
  const std::vector<float> nu = pasted_normals(normals, size, upright, w, h, &ru);
  const std::vector<float> nr = pasted_normals(normals, size, rotated, w, h, &rr);
  const size_t pp = static_cast<size_t>(w) * h;
  double worst = 0;
  int compared = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Point2 q = turn.apply({static_cast<double>(x), static_cast<double>(y)});
      const int qx = static_cast<int>(std::lround(q.x)), qy = static_cast<int>(std::lround(q.y));
      if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
      auto alpha = [](const PasteRegion& r, int px, int py) {
        if (px < r.x0 || py < r.y0 || px >= r.x0 + r.width || py >= r.y0 + r.height) return 0.0f;
        return r.alpha[static_cast<size_t>(py - r.y0) * r.width + (px - r.x0)];
      };
      if (alpha(ru, x, y) < 1 || alpha(rr, qx, qy) < 1) continue;
      if (std::hypot(q.x - qx, q.y - qy) > 1e-6) continue;  // only exact pixel correspondences
      const size_t i = static_cast<size_t>(y) * w + x, j = static_cast<size_t>(qy) * w + qx;
      // The upright normal turned counter-clockwise (+t about +Z with +Y up).
      const double ex = std::cos(t) * nu[i] - std::sin(t) * nu[pp + i];
      const double ey = std::sin(t) * nu[i] + std::cos(t) * nu[pp + i];
      worst = std::max({worst, std::abs(nr[j] - ex), std::abs(nr[pp + j] - ey),
                        static_cast<double>(std::abs(nr[2 * pp + j] - nu[2 * pp + i]))});
      ++compared;
    }
  if (degrees == 90) {
    ASSERT_GT(compared, 1000);
  }
  if (compared > 0) {
    EXPECT_LT(worst, 1e-4) << compared << " pixels compared";
  }

  sh::RgbLight light;
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  for (double& v : light) v = g(rng);
  const sh::RgbLight lu = rotate_light_to_photo(light, upright), lr = rotate_light_to_photo(light, rotated);
  for (int k = 0; k < 20; ++k) {
    sh::Vec3 d = {g(rng), g(rng), g(rng)};
    const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (double& v : d) v /= n;
    const sh::Vec3 turned = {std::cos(t) * d[0] - std::sin(t) * d[1], std::sin(t) * d[0] + std::cos(t) * d[1], d[2]};
    const auto a = sh::light_eval(lu, d), b = sh::light_eval(lr, turned);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-9);
    // Visibility is a function of direction too: the same turn applies.
    std::vector<float> vu(9), vr(9);
    for (int i = 0; i < 9; ++i) vu[i] = vr[i] = static_cast<float>(light[i]);
    rotate_visibility_to_photo(vu.data(), 1, upright);
    rotate_visibility_to_photo(vr.data(), 1, rotated);
    sh::ShCoeffs fu, fr;
    for (int i = 0; i < 9; ++i) {
      fu[i] = vu[i];
      fr[i] = vr[i];
    }
    EXPECT_NEAR(sh::sh_eval(fu, d), sh::sh_eval(fr, turned), 1e-4);
  }
}

INSTANTIATE_TEST_SUITE_P(Turns, RotatedPhoto, ::testing::Values(90.0, 30.0));

}  // namespace
}  // namespace facetool
