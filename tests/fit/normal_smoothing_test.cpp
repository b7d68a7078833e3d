// The head-masked normal smoothing against a plain two-dimensional Gaussian sum, on random
// normals and a random head shape; pixels off the head untouched; sigma 0 a no-op; bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/util/error.h"
#include "libs/fit/normal_smoothing.h"

namespace facetool {
namespace {

struct Field {
  int width = 0, height = 0;
  std::vector<float> normal;  // planar [3]
  std::vector<uint8_t> head;
};

// Unit normals leaning at most ~60 degrees from +Z over a head made of two overlapping discs
// touching the image's left edge (so the kernel meets the edge too); off the head the value 7
// (not a normal: it must stay as it is).
Field random_field(int width, int height, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> lean(-1.0f, 1.0f);
  Field f{width, height, std::vector<float>(3 * static_cast<size_t>(width) * height, 7.0f),
          std::vector<uint8_t>(static_cast<size_t>(width) * height, 0)};
  const size_t plane = f.head.size();
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double a = std::hypot(x - 0.3 * width, y - 0.5 * height), b = std::hypot(x - 0.6 * width, y - 0.4 * height);
      const size_t p = static_cast<size_t>(y) * width + x;
      if (a > 0.32 * width && b > 0.25 * width) continue;
      f.head[p] = 1;
      const float n[3] = {lean(random), lean(random), 1.0f};
      const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      for (int c = 0; c < 3; ++c) f.normal[c * plane + p] = n[c] / length;
    }
  return f;
}

// The definition: per head pixel, the sum over head pixels within the kernel's square reach of
// exp(-(dx^2 + dy^2) / (2 sigma^2)) times their normal, normalised.
std::vector<float> reference(const Field& f, double sigma) {
  const size_t plane = f.head.size();
  const int reach = static_cast<int>(std::ceil(3 * sigma));
  std::vector<float> out = f.normal;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const size_t p = static_cast<size_t>(y) * f.width + x;
      if (!f.head[p]) continue;
      double n[3] = {0, 0, 0};
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach; dx <= reach; ++dx) {
          const int u = x + dx, v = y + dy;
          if (u < 0 || v < 0 || u >= f.width || v >= f.height) continue;
          const size_t q = static_cast<size_t>(v) * f.width + u;
          if (!f.head[q]) continue;
          const double w = std::exp(-(dx * dx + dy * dy) / (2 * sigma * sigma));
          for (int c = 0; c < 3; ++c) n[c] += w * f.normal[c * plane + q];
        }
      const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      for (int c = 0; c < 3; ++c) out[c * plane + p] = static_cast<float>(n[c] / length);
    }
  return out;
}

TEST(NormalSmoothing, MatchesThePlainGaussianSumOverTheHead) {
  for (double sigma : {0.6, 1.7, 3.0}) {
    Field f = random_field(61, 47, 5);
    const std::vector<float> before = f.normal, want = reference(f, sigma);
    smooth_normals(f.normal, f.head, f.width, f.height, sigma);
    const size_t plane = f.head.size();
    double changed = 0;
    for (size_t p = 0; p < plane; ++p)
      for (int c = 0; c < 3; ++c) {
        ASSERT_NEAR(f.normal[c * plane + p], want[c * plane + p], 2e-5) << "sigma " << sigma << " pixel " << p;
        if (f.head[p]) {
          changed += std::fabs(want[c * plane + p] - before[c * plane + p]);
        } else {
          ASSERT_EQ(f.normal[c * plane + p], 7.0f) << "off the head";
        }
      }
    EXPECT_GT(changed, 10.0) << "the smoothing moved nothing: the comparison would not catch a no-op";
  }
}

TEST(NormalSmoothing, UnitLengthAndSigmaZeroIsANoOp) {
  Field f = random_field(40, 40, 9);
  const std::vector<float> before = f.normal;
  smooth_normals(f.normal, f.head, f.width, f.height, 0.0);
  EXPECT_EQ(f.normal, before);
  smooth_normals(f.normal, f.head, f.width, f.height, 2.5);
  const size_t plane = f.head.size();
  for (size_t p = 0; p < plane; ++p) {
    if (!f.head[p]) continue;
    ASSERT_NEAR(std::sqrt(f.normal[p] * f.normal[p] + f.normal[plane + p] * f.normal[plane + p] +
                          f.normal[2 * plane + p] * f.normal[2 * plane + p]),
                1.0, 1e-5);
  }
}

TEST(NormalSmoothing, RefusesBadInput) {
  Field f = random_field(20, 10, 1);
  EXPECT_THROW(smooth_normals(f.normal, f.head, f.width, f.height, -1.0), Error);
  EXPECT_THROW(smooth_normals(f.normal, f.head, f.width, f.height, std::nan("")), Error);
  EXPECT_THROW(smooth_normals(f.normal, f.head, f.width + 1, f.height, 1.0), Error);
}

}  // namespace
}  // namespace facetool
