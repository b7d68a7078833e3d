// Debian blender-data's 8 studio-light EXRs (DWAB-compressed) as synth light sources: each loads,
// its SH projection's ambient term matches the map's own solid-angle-weighted mean radiance, and
// clamping the light to be non-negative on the sphere only adds light.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "core/sh/envmap_projection.h"
#include "libs/synth/light_source.h"
#include "core/util/math_constants.h"

namespace facetool {
namespace {


TEST(BlenderStudioLights, EachLoadsWithTheAmbientTermOfItsMap) {
  if (!std::filesystem::is_directory(kBlenderStudioLightsDir))
    GTEST_SKIP() << kBlenderStudioLightsDir
                 << " is absent: install Debian's blender-data package to test its lights";
  const std::vector<LightSource> sources = load_light_sources({kBlenderStudioLightsDir});
  ASSERT_EQ(sources.size(), 8u) << "blender-data ships 8 world EXRs (license.txt is skipped)";
  for (const LightSource& source : sources) {
    ASSERT_TRUE(source.environment) << source.name;
    const sh::EnvironmentMap& map = *source.environment;
    ASSERT_GT(map.width, 0);
    // Independent ambient term: L_0 = Y_0 * integral of L = 2 sqrt(pi) * mean radiance, with
    // the mean weighted by each row's solid angle (sin of the polar angle).
    for (int c = 0; c < 3; ++c) {
      double weighted = 0.0, weights = 0.0;
      for (int y = 0; y < map.height; ++y) {
        const double weight = std::sin(kPi * (y + 0.5) / map.height);
        for (int x = 0; x < map.width; ++x) {
          weighted += weight * map.rgb[(static_cast<size_t>(y) * map.width + x) * 3 + c];
          weights += weight;
        }
      }
      const double expected = 2.0 * std::sqrt(kPi) * weighted / weights;
      const size_t dc = static_cast<size_t>(c) * sh::kCoeffCount;  // channel-major
      const double projected = sh::project_environment_map(map)[dc];
      EXPECT_NEAR(projected, expected, 1e-3 * expected) << source.name << " channel " << c;
      // make_light_nonnegative projects max(0, L(w)) back: it can only raise the ambient term.
      ASSERT_TRUE(std::isfinite(source.light[dc])) << source.name;
      EXPECT_GE(source.light[dc], projected * (1.0 - 1e-6)) << source.name << " channel " << c;
    }
  }
}

}  // namespace
}  // namespace facetool
