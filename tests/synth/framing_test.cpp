// Framings in synth: the camera's projection against its rays, v1's rays unchanged, the zoom on a
// rendered sphere, and simulated photo edges (coverage, ring-mean fill, mask cut) against plain
// computations.
#include <gtest/gtest.h>

#include <cmath>

#include "core/util/error.h"
#include "core/util/math_constants.h"
#include "libs/image/border_fill.h"
#include "libs/synth/photo_edge.h"
#include "libs/synth/generator_settings.h"
#include "libs/synth/sample_generator.h"
#include "synth_test_support.h"

namespace facetool {
namespace {

const CropFraming kOdd = parse_framing("zoom 1.7 centre 0.42 0.55 border ring-mean", "test");

TEST(SynthFraming, ProjectionIsTheInverseOfTheRays) {
  Random random(3);
  for (const CropFraming& framing : {v1_framing(), v2_framing(), kOdd}) {
    Camera camera;
    camera.width = 96;
    camera.height = 80;
    camera.horizontal_fov_deg = 21.0;
    camera.framing = framing;
    for (int k = 0; k < 50; ++k) {
      const Vec3f p{static_cast<float>(random.uniform(-1, 1)), static_cast<float>(random.uniform(-1, 1)),
                    static_cast<float>(random.uniform(-1, 1))};
      const std::array<double, 2> pixel = camera.project(p);
      const Vec3f ray = camera.ray_direction(pixel[0], pixel[1]);
      const Vec3f to_p = normalized(p - camera.eye());
      EXPECT_NEAR(dot(ray, to_p), 1.0, 1e-6) << framing_text(framing);
      // The framing maps v1's crop units: (pixel + 0.5) / size.
      Camera v1 = camera;
      v1.framing = CropFraming{};
      const std::array<double, 2> base = v1.project(p);
      EXPECT_NEAR((pixel[0] + 0.5) / 96, framing.to_x((base[0] + 0.5) / 96), 1e-9);
      EXPECT_NEAR((pixel[1] + 0.5) / 80, framing.to_y((base[1] + 0.5) / 80), 1e-9);
    }
  }
}

TEST(SynthFraming, V1RaysAreBitForBitTheFormulaWithoutAFraming) {
  Camera camera;
  camera.width = 64;
  camera.height = 48;
  camera.horizontal_fov_deg = 23.3;
  for (int y = 0; y < 48; y += 5)
    for (int x = 0; x < 64; x += 3) {
      const double half_width = std::tan(0.5 * 23.3 * kPi / 180.0);
      const double half_height = half_width * 48 / 64;
      const double u = (2.0 * (x + 0.5) / 64 - 1.0) * half_width;
      const double v = (1.0 - 2.0 * (y + 0.5) / 48) * half_height;
      const Vec3f want = normalized(Vec3f{static_cast<float>(u), static_cast<float>(v), -1.0f});
      const Vec3f got = camera.ray_direction(x, y);
      EXPECT_EQ(got.x, want.x);
      EXPECT_EQ(got.y, want.y);
      EXPECT_EQ(got.z, want.z);
    }
}

TEST(SynthFraming, PhotoEdgeCoverageIsTheAreaInsideTheEdges) {
  Random random(8);
  const int w = 40, h = 40;
  int drawn = 0;
  for (int k = 0; k < 20; ++k) {
    const PhotoEdges edges = sample_photo_edges(random, PhotoEdgeSampling{1.0});
    ASSERT_GE(edges.count, 1);
    drawn += edges.count;
    const std::vector<float> coverage = photo_edge_coverage(edges, w, h);
    double error = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        // Plain: 32 x 32 point samples of the pixel.
        int in = 0;
        for (int j = 0; j < 32; ++j)
          for (int i = 0; i < 32; ++i) {
            const double qx = (x + (i + 0.5) / 32) / w - 0.5, qy = (y + (j + 0.5) / 32) / h - 0.5;
            bool inside = true;
            for (int e = 0; e < edges.count; ++e) inside = inside && edges.nx[e] * qx + edges.ny[e] * qy <= edges.offset[e];
            in += inside;
          }
        const double area = in / 1024.0;
        EXPECT_NEAR(coverage[y * w + x], area, 0.2);
        error += std::abs(coverage[y * w + x] - area) / (w * h);
      }
    EXPECT_LT(error, 0.01);
  }
  EXPECT_GT(drawn, 20);  // some corners
  Random none(1);
  EXPECT_EQ(sample_photo_edges(none, PhotoEdgeSampling{0.0}).count, 0);
}

SampleGenerator sphere_generator(const std::string& light_file, const CropFraming& framing, double edges) {
  SynthSettings settings;
  settings.camera.width = settings.camera.height = 48;
  settings.camera.min_fov_deg = settings.camera.max_fov_deg = 22.5;
  settings.camera.framing = framing;
  settings.photo_edges.fraction = edges;
  settings.direction_count = 16;
  settings.pose.max_roll_deg = settings.pose.max_pitch_deg = settings.pose.max_yaw_deg = 0;
  FaceSource faces;
  faces.mesh = std::make_shared<const FaceMesh>(testing::make_sphere(24, 48));
  return SampleGenerator(faces, load_light_sources({light_file}), BackgroundSource(), make_reference_renderer(),
                         settings);
}

TEST(SynthFraming, ZoomEnlargesTheRenderAndPhotoEdgesFillAsAlignmentDoes) {
  testing::ScratchDir dir("synth-framing");
  testing::write_text(dir.file("light.txt"), "1 1 1\n0.3 0.3 0.3\n0.2 0.2 0.2\n0.1 0.1 0.1\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n");
  const CropFraming zoom2 = parse_framing("zoom 2 centre 0.5 0.5 border ring-mean", "test");
  const SampleGenerator v1 = sphere_generator(dir.file("light.txt"), v1_framing(), 0.0);
  const SampleGenerator plain = sphere_generator(dir.file("light.txt"), zoom2, 0.0);
  const SampleGenerator edged = sphere_generator(dir.file("light.txt"), zoom2, 1.0);
  EXPECT_EQ(v1.settings_description().find("framing"), std::string::npos);  // v1 runs: as before
  EXPECT_NE(plain.settings_description().find("framing zoom 2"), std::string::npos);
  EXPECT_NE(plain.settings_fingerprint(), edged.settings_fingerprint());

  const SynthSample a = v1.generate(4, 0), b = plain.generate(4, 0), c = edged.generate(4, 0);
  EXPECT_EQ(a.framing, "");
  EXPECT_EQ(b.framing, framing_text(zoom2));
  // The sphere's silhouette (radius ~21 pixels at v1): a quarter of the pixels at zoom 0.5
  // (within the pixel quantisation), and about the same centre.
  const SynthSample half =
      sphere_generator(dir.file("light.txt"), parse_framing("zoom 0.5 centre 0.5 0.5 border ring-mean", "test"), 0.0)
          .generate(4, 0);
  double head_a = 0, head_half = 0, centre_a = 0, centre_half = 0;
  for (size_t p = 0; p < a.plane(); ++p) {
    head_a += a.depth[p] > 0;
    head_half += half.depth[p] > 0;
    centre_a += (a.depth[p] > 0) * static_cast<double>(p % 48);
    centre_half += (half.depth[p] > 0) * static_cast<double>(p % 48);
  }
  EXPECT_NEAR(head_half / head_a, 0.25, 0.02);
  EXPECT_NEAR(centre_half / head_half, centre_a / head_a, 0.1);

  // Photo edges: the same sample (edges have their own random stream), then beyond the edges the
  // ring mean of the unedged image and the mask cut (libs/image/border_fill.h).
  ASSERT_GT(c.photo_edges, 0);
  Random stream(derive_seed(c.sample_seed, 7));  // kPhotoEdge in sample_generator.cpp
  const PhotoEdges edges = sample_photo_edges(stream, PhotoEdgeSampling{1.0});
  ASSERT_EQ(edges.count, c.photo_edges);
  const std::vector<float> coverage = photo_edge_coverage(edges, c.width, c.height);
  const std::array<float, 3> fill = ring_mean_colour(b.image, coverage, c.width, c.height, border_ring_width(48));
  const size_t plane = c.plane();
  int outside = 0;
  for (size_t p = 0; p < plane; ++p) {
    EXPECT_EQ(c.mask[p], coverage[p] < 0.5f ? 0.0f : b.mask[p]);
    for (int k = 0; k < 3; ++k) {
      const float want = coverage[p] * b.image[k * plane + p] + (1 - coverage[p]) * fill[k];
      EXPECT_NEAR(c.image[k * plane + p], want, 1e-6);
      EXPECT_EQ(c.albedo[k * plane + p], b.albedo[k * plane + p]);
    }
    outside += coverage[p] == 0;
  }
  EXPECT_GT(outside, 0);
}

TEST(SynthFraming, PhotoEdgesNeedTheRingMeanFill) {
  testing::ScratchDir dir("synth-framing-errors");
  testing::write_text(dir.file("light.txt"), "1 1 1\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n");
  EXPECT_THROW(sphere_generator(dir.file("light.txt"), v1_framing(), 0.5), Error);
}

}  // namespace
}  // namespace facetool
