// Visibility against closed forms: an open plane gives the upper hemisphere's SH coefficients
// (within the stated 872-direction sampling error), a point inside a closed box sees nothing.
#include <cmath>
#include <cstdio>

#include "core/sh/sh_basis.h"
#include "core/sh/sphere_samples.h"
#include "libs/synth/ray_scene.h"
#include "libs/synth/visibility.h"
#include "synth_test_support.h"
#include "core/util/math_constants.h"

namespace facetool {
namespace {


// Closed form of integral over {w.n > 0} of Y_i(w): the hemisphere indicator is zonal about n
// with Funk-Hecke factors sqrt(pi) (l = 0), pi (l = 1) and 0 (l = 2, since the integral of
// P_2 over [0, 1] vanishes): v_0 = sqrt(pi), v_i = pi Y_i(n) for i = 1..3, v_4..8 = 0.
std::array<double, 9> analytic_hemisphere(Vec3f n) {
  double y[9];
  sh::sh_basis(n.x, n.y, n.z, y);
  std::array<double, 9> v{};
  v[0] = std::sqrt(kPi);
  for (int i = 1; i < 4; ++i) v[i] = kPi * y[i];
  return v;
}

TEST(SynthVisibility, OpenPlaneGivesTheUpperHemisphere) {
  // A 200 x 200 square through the origin, facing +Z, with the point at its centre.
  const std::vector<Vec3f> positions = {{-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0}};
  const RayScene plane(positions, {{0, 1, 2}, {0, 2, 3}});
  const VisibilitySampler sampler(872);
  float rays_result[9], sampled_open[9];
  const Vec3f n{0, 0, 1};
  const int64_t cast = sampler.integrate(plane, {0, 0, 0}, n, 1e-3f, rays_result);
  EXPECT_EQ(cast, 436);  // the Fibonacci set has exactly half of its 872 directions above z = 0
  sampler.open_hemisphere(n, sampled_open);
  const auto exact = analytic_hemisphere(n);
  for (int i = 0; i < 9; ++i) {
    // Every ray above the plane escapes: the ray-cast sum is the sampled hemisphere itself.
    EXPECT_FLOAT_EQ(rays_result[i], sampled_open[i]) << "coefficient " << i;
    // Stated sampling error of the 872-direction Fibonacci set for a hemisphere about an axis
    // aligned with its bands: the z bands put the horizon between two rows, so v_0 and v_2 are
    // exact up to rounding and the others (azimuthal sums) are within 0.01.
    const double tolerance = (i == 0 || i == 2) ? 1e-5 : 0.01;
    EXPECT_NEAR(rays_result[i], exact[i], tolerance) << "coefficient " << i;
  }
}

TEST(SynthVisibility, SampledHemisphereMatchesClosedFormForTiltedNormals) {
  // For normals not aligned with the bands the horizon cuts rows: stated error <= 0.03 per
  // coefficient (about 1% of v_0 = 1.77) for 872 directions.
  const VisibilitySampler sampler(872);
  double worst = 0.0;
  for (const Vec3f n : {Vec3f{1, 2, 3}, Vec3f{-0.3f, 0.1f, 0.9f}, Vec3f{0.7f, -0.7f, 0.1f},
                        Vec3f{0, 1, 0}, Vec3f{-1, -1, -1}}) {
    const Vec3f unit = normalized(n);
    float sampled[9];
    sampler.open_hemisphere(unit, sampled);
    const auto exact = analytic_hemisphere(unit);
    for (int i = 0; i < 9; ++i) {
      worst = std::max(worst, std::fabs(sampled[i] - exact[i]));
      EXPECT_NEAR(sampled[i], exact[i], 0.03) << "coefficient " << i;
    }
  }
  std::printf("largest sampling error of the 872-direction hemisphere: %.4f\n", worst);
}

TEST(SynthVisibility, TiltedPlaneRaysAgreeWithTheSampledHemisphere) {
  const Vec3f n = normalized({1, 2, 3});
  const Vec3f u = normalized(cross(n, {0, 0, 1})), v = cross(n, u);
  const std::vector<Vec3f> positions = {u * -100 + v * -100, u * 100 + v * -100,
                                        u * 100 + v * 100, u * -100 + v * 100};
  const RayScene plane(positions, {{0, 1, 2}, {0, 2, 3}});
  const VisibilitySampler sampler(872);
  float rays_result[9], sampled_open[9];
  sampler.integrate(plane, {0, 0, 0}, n, 1e-3f, rays_result);
  sampler.open_hemisphere(n, sampled_open);
  for (int i = 0; i < 9; ++i) EXPECT_FLOAT_EQ(rays_result[i], sampled_open[i]) << i;
}

TEST(SynthVisibility, PointInsideAClosedBoxSeesNothing) {
  // The cube [-1, 1]^3, 12 triangles; visibility from its centre and an off-centre point.
  std::vector<Vec3f> corners;
  for (int k = 0; k < 8; ++k)
    corners.push_back({k & 1 ? 1.0f : -1.0f, k & 2 ? 1.0f : -1.0f, k & 4 ? 1.0f : -1.0f});
  const std::vector<std::array<int32_t, 3>> faces = {
      {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
      {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  const RayScene box(corners, faces);
  const VisibilitySampler sampler(872);
  for (const Vec3f p : {Vec3f{0, 0, 0}, Vec3f{0.9f, -0.5f, 0.2f}}) {
    for (const Vec3f n : {Vec3f{0, 0, 1}, normalized({1, -2, 0.5f})}) {
      float v[9];
      const int64_t cast = sampler.integrate(box, p, n, 1e-3f, v);
      EXPECT_GT(cast, 400);
      for (int i = 0; i < 9; ++i) EXPECT_EQ(v[i], 0.0f) << "coefficient " << i;
    }
  }
}

TEST(SynthVisibility, GroupedPointsEqualSinglePoints) {
  // Half-open geometry: a floor and a wall, points spread over the floor.
  const std::vector<Vec3f> positions = {{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5},
                                        {-5, 0, -1}, {5, 0, -1}, {5, 3, -1}, {-5, 3, -1}};
  const RayScene scene(positions, {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}});
  const VisibilitySampler sampler(872);
  Vec3f points[16], normals[16];
  for (int k = 0; k < 16; ++k) {
    points[k] = {-2.0f + 0.25f * k, 0.0f, -0.9f + 0.2f * (k % 5)};
    normals[k] = normalized({0.05f * (k % 3), 1.0f, 0.0f});
  }
  float grouped[16 * 9];
  sampler.integrate_group(scene, points, normals, 16, 1e-3f, grouped);
  for (int k = 0; k < 16; ++k) {
    float single[9];
    sampler.integrate(scene, points[k], normals[k], 1e-3f, single);
    for (int i = 0; i < 9; ++i) EXPECT_FLOAT_EQ(grouped[9 * k + i], single[i]) << k << " " << i;
  }
  // The wall hides part of the sky near it: less visible than an open floor point.
  float open[9];
  sampler.open_hemisphere(normals[0], open);
  EXPECT_LT(grouped[0], open[0] - 0.1f);
}

// Regression for uninitialised packet lanes (issue 10): integrate_group must cast fully defined
// packets for every direction count (including tiny and odd ones) and every group size, with
// normals that leave some lanes inactive for many directions. Reference: one rtcIntersect1 ray
// per (point, direction) through RayScene::intersect, summed in double; the sampler sums float
// basis values in double, so 1e-5 absolute covers the rounding (coefficients are O(1)).
TEST(SynthVisibility, GroupsMatchOneRayAtATimeForAnyDirectionCountAndGroupSize) {
  const std::vector<Vec3f> positions = {{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5},
                                        {-5, 0, -1}, {5, 0, -1}, {5, 3, -1}, {-5, 3, -1}};
  const RayScene scene(positions, {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}});
  for (const int directions : {1, 2, 7, 8, 9, 17, 31, 872, 1001}) {
    const VisibilitySampler sampler(directions);
    const std::vector<sh::Vec3> dirs = sh::fibonacci_sphere(directions);
    for (const int count : {1, 3, 8, 15, 16}) {
      Vec3f points[16], normals[16];
      for (int k = 0; k < count; ++k) {
        points[k] = {-2.0f + 0.25f * k, 0.0f, -0.85f + 0.2f * (k % 5)};
        // Normals from straight up to almost horizontal and facing the wall or away from it.
        const float tilt = 0.3f * (k % 4);
        normals[k] = normalized({k % 2 ? tilt : -tilt, 1.0f, k % 3 ? 0.4f : -0.4f});
      }
      float grouped[16 * 9];
      const int64_t cast = sampler.integrate_group(scene, points, normals, count, 1e-3f, grouped);
      int64_t expected_cast = 0;
      for (int k = 0; k < count; ++k) {
        double reference[9] = {};
        const Vec3f origin = points[k] + normals[k] * 1e-3f;
        for (const sh::Vec3& d : dirs) {
          const Vec3f w{static_cast<float>(d[0]), static_cast<float>(d[1]),
                        static_cast<float>(d[2])};
          if (w.x * normals[k].x + w.y * normals[k].y + w.z * normals[k].z <= 0.0f) continue;
          ++expected_cast;
          if (scene.intersect(origin, w).triangle >= 0) continue;
          double y[9];
          sh::sh_basis(d[0], d[1], d[2], y);
          for (int i = 0; i < 9; ++i) reference[i] += y[i] * 4.0 * kPi / directions;
        }
        for (int i = 0; i < 9; ++i)
          EXPECT_NEAR(grouped[9 * k + i], reference[i], 1e-5)
              << directions << " directions, group of " << count << ", point " << k
              << ", coefficient " << i;
      }
      EXPECT_EQ(cast, expected_cast) << directions << " directions, group of " << count;
    }
  }
}

}  // namespace
}  // namespace facetool
