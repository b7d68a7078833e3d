// Tests of the Fibonacci direction sets and of projection with 4 pi / N weights.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/sh/sh_basis.h"
#include "core/sh/sh_eval.h"
#include "core/sh/sh_projection.h"
#include "core/sh/sphere_samples.h"
#include "core/util/error.h"

namespace facetool::sh {
namespace {

TEST(SphereSamples, AreUnitDeterministicAndBalanced) {
  for (int count : {1, 9, kVisibilitySampleCount, kIlluminationSampleCount}) {
    const std::vector<Vec3> a = fibonacci_sphere(count), b = fibonacci_sphere(count);
    ASSERT_EQ(a.size(), static_cast<size_t>(count));
    Vec3 mean{0, 0, 0};
    for (size_t s = 0; s < a.size(); ++s) {
      EXPECT_NEAR(a[s][0] * a[s][0] + a[s][1] * a[s][1] + a[s][2] * a[s][2], 1.0, 1e-12);
      EXPECT_EQ(a[s], b[s]);
      for (int c = 0; c < 3; ++c) mean[c] += a[s][c] / count;
    }
    if (count >= 872) {
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], 0.0, 2.0 / count) << count;
    }
  }
  EXPECT_THROW(fibonacci_sphere(0), Error);
}

TEST(ShProjection, RecoversAnShFunction) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ShCoeffs f{};
  for (double& v : f) v = u(rng);
  // Quadrature error of the lattice for degree-4 integrands: measured ~1e-6 at 64,000 and
  // ~1e-3 at 872 directions.
  const ShCoeffs dense = project_function(fibonacci_sphere(kIlluminationSampleCount),
                                          [&](const Vec3& w) { return sh_eval(f, w); });
  const ShCoeffs sparse = project_function(fibonacci_sphere(kVisibilitySampleCount),
                                           [&](const Vec3& w) { return sh_eval(f, w); });
  for (int i = 0; i < kCoeffCount; ++i) {
    EXPECT_NEAR(dense[i], f[i], 1e-5) << i;
    EXPECT_NEAR(sparse[i], f[i], 1e-2) << i;
  }
}

TEST(ShProjection, MismatchedSizesAreAnError) {
  EXPECT_THROW(project_samples(fibonacci_sphere(4), {1.0, 2.0}), Error);
  EXPECT_THROW(project_samples({}, {}), Error);
}

}  // namespace
}  // namespace facetool::sh
