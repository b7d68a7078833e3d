// Printed (never asserted) generator timings at 128x128 with 872 directions: per-phase times on
// one thread, then samples/s and Mrays/s of run_synth on 2 threads.
#include <chrono>
#include <cstdio>

#include "libs/synth/synth_runner.h"
#include "synth_test_support.h"

namespace facetool {
namespace {

TEST(SynthPerformance, PrintsSamplesPerSecondAndRaysPerSecond) {
  const std::string model_dir = testing::ict_face_model_dir();
  FACETOOL_REQUIRE_SHARED(model_dir);
  FACETOOL_REQUIRE_SHARED(testing::hdri_dir());
  const auto load_start = std::chrono::steady_clock::now();
  FaceSource faces;
  faces.model = std::make_shared<const FaceModel>(FaceModel::load(model_dir));
  SampleGenerator generator(faces, load_light_sources({testing::hdri_dir()}), BackgroundSource(),
                            make_reference_renderer(), SynthSettings());
  const double load_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - load_start).count();
  std::printf("load: face model + 5 HDRIs %.2f s\n", load_seconds);

  double geometry = 0, visibility = 0, shading = 0;
  int64_t rays = 0, pixels = 0;
  const int samples = 4;
  for (int k = 0; k < samples; ++k) {
    const SynthSample s = generator.generate(7, k);
    geometry += s.seconds_geometry;
    visibility += s.seconds_visibility;
    shading += s.seconds_shading;
    rays += s.rays_cast;
    for (float m : s.mask) pixels += m > 0.5f;
  }
  std::printf("one thread, per sample (thread CPU time): geometry %.3f s, visibility %.3f s (%.1f Mrays per CPU s, %.0f "
              "face pixels, %.0f rays/pixel), shading %.3f s\n",
              geometry / samples, visibility / samples, rays / visibility / 1e6,
              static_cast<double>(pixels) / samples, static_cast<double>(rays) / pixels,
              shading / samples);

  testing::ScratchDir out("synth-perf");
  SynthRunOptions options;
  options.output_dir = out.path();
  options.count = 12;
  options.seed = 11;
  options.threads = 2;
  const SynthRunReport report = run_synth(generator, options);
  std::printf("run_synth, 2 threads: %lld samples in %.2f s = %.2f samples/s, %.1f Mrays/s "
              "(wall), %.3f CPU s per sample\n",
              static_cast<long long>(report.generated), report.seconds,
              report.generated / report.seconds, report.rays_cast / report.seconds / 1e6,
              report.cpu_seconds / report.generated);
}

}  // namespace
}  // namespace facetool
