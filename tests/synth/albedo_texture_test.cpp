// Albedo textures: the frame and look-up against closed forms, the files, and synth painting them
// (the texture's colour where it is seen, the paper's samples unchanged when none is painted).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/util/error.h"
#include "libs/io/exr_io.h"
#include "libs/synth/albedo_texture.h"
#include "libs/synth/component_renderer.h"
#include "libs/synth/random.h"
#include "libs/synth/sample_generator.h"
#include "synth_test_support.h"
#include "tests/support/error_text.h"

namespace facetool {
namespace {

using testing::error_text;

TEST(AlbedoTexture, FrameIsTheFaceRegionsBoundingSquareGrownByATenth) {
  FaceMesh mesh;
  mesh.reference_positions = {{-1, -2, 0}, {3, 2, 0.5f}, {10, 10, 0}};
  mesh.fit_vertices = {0, 1};  // the third vertex is not in the face region
  const AlbedoTextureFrame frame = albedo_texture_frame(mesh, 64);
  EXPECT_FLOAT_EQ(frame.span, 4.4f);
  EXPECT_FLOAT_EQ(frame.left, 1.0f - 2.2f);
  EXPECT_FLOAT_EQ(frame.top, 0.0f + 2.2f);
  float u, v;
  albedo_texel(frame, {frame.left, frame.top, 0}, false, u, v);  // the upper-left corner
  EXPECT_NEAR(u, -0.5f, 1e-5f);
  EXPECT_NEAR(v, -0.5f, 1e-5f);
  albedo_texel(frame, {frame.left + frame.span, frame.top - frame.span, 0}, false, u, v);
  EXPECT_NEAR(u, 63.5f, 1e-4f);
  EXPECT_NEAR(v, 63.5f, 1e-4f);
  albedo_texel(frame, {frame.left, 0.7f, 0}, true, u, v);  // mirrored: the right edge
  EXPECT_NEAR(u, 63.5f, 1e-4f);
  EXPECT_THROW(albedo_texture_frame(FaceMesh{}, 64), Error);
}

AlbedoTexture ramp_texture(int size) {
  AlbedoTexture t;
  t.frame = {size, -1.0f, 1.0f, 2.0f};
  const size_t plane = static_cast<size_t>(size) * size;
  t.rgb.resize(3 * plane);
  t.weight.assign(plane, 1.0f);
  for (int v = 0; v < size; ++v)
    for (int u = 0; u < size; ++u) {
      const size_t p = static_cast<size_t>(v) * size + u;
      t.rgb[p] = 0.1f + 0.01f * u;
      t.rgb[plane + p] = 0.2f + 0.005f * v;
      t.rgb[2 * plane + p] = 0.4f;
      t.weight[p] = u < size / 2 ? 1.0f : 0.5f;
    }
  t.source = "ramp";
  return t;
}

TEST(AlbedoTexture, BilinearLookUpReproducesALinearTexture) {
  const AlbedoTexture t = ramp_texture(32);
  Random random(4);
  for (int k = 0; k < 200; ++k) {
    // Points whose texel coordinates lie inside [0, 31]: no clamping.
    const Vec3f p{static_cast<float>(random.uniform(-0.95, 0.95)), static_cast<float>(random.uniform(-0.95, 0.95)), 0};
    for (const bool mirror : {false, true}) {
      Vec3f rgb;
      float weight;
      sample_albedo_texture(t, p, mirror, rgb, weight);
      const float x = mirror ? -p.x : p.x;  // the frame's centre line is x = 0
      const float u = (x + 1.0f) / 2.0f * 32 - 0.5f, v = (1.0f - p.y) / 2.0f * 32 - 0.5f;
      EXPECT_NEAR(rgb[0], 0.1f + 0.01f * u, 1e-5f);
      EXPECT_NEAR(rgb[1], 0.2f + 0.005f * v, 1e-5f);
      EXPECT_NEAR(rgb[2], 0.4f, 1e-6f);
      if (u < 15) {
        EXPECT_NEAR(weight, 1.0f, 1e-6f);
      }
      if (u > 16) {
        EXPECT_NEAR(weight, 0.5f, 1e-6f);
      }
    }
  }
  // Outside the frame the edge texel holds.
  Vec3f rgb;
  float weight;
  sample_albedo_texture(t, {5.0f, 0.0f, 0.0f}, false, rgb, weight);
  EXPECT_NEAR(rgb[0], 0.1f + 0.01f * 31, 1e-5f);
  // The weighted mean: weights 1 on the left half, 0.5 on the right.
  const Vec3f mean = mean_albedo(t);
  double sum = 0, total = 0;
  for (int u = 0; u < 32; ++u) {
    const double w = u < 16 ? 1.0 : 0.5;
    sum += w * (0.1 + 0.01 * u);
    total += w;
  }
  EXPECT_NEAR(mean[0], sum / total, 1e-5);
}

TEST(AlbedoTexture, FilesRoundTripAndBadOnesAreNamed) {
  testing::ScratchDir dir("facetool_albedo_texture_test");
  const AlbedoTexture t = ramp_texture(16);
  std::filesystem::create_directories(dir.file("textures"));
  write_albedo_texture(dir.file("textures/a.exr"), t);
  const AlbedoTexture back = read_albedo_texture(dir.file("textures/a.exr"));
  EXPECT_EQ(back.frame, t.frame);
  EXPECT_EQ(back.rgb, t.rgb);
  EXPECT_EQ(back.weight, t.weight);
  EXPECT_EQ(back.source, "ramp");
  EXPECT_EQ(read_albedo_textures(dir.file("textures")).size(), 1u);
  // Another frame in the same folder.
  AlbedoTexture other = t;
  other.frame.span = 3.0f;
  write_albedo_texture(dir.file("textures/b.exr"), other);
  EXPECT_NE(error_text([&] { read_albedo_textures(dir.file("textures")); }).find("b.exr' has another frame"),
            std::string::npos);
  // A plain EXR: no frame.
  LayeredImage plain(16, 16, {"R", "G", "B", "A"});
  write_exr_atomically(dir.file("plain.exr"), plain);
  const std::string message = error_text([&] { read_albedo_texture(dir.file("plain.exr")); });
  EXPECT_NE(message.find("plain.exr' has no facetool:albedo_texture_frame"), std::string::npos) << message;
  EXPECT_NE(message.find("facetool unwrap"), std::string::npos) << message;
  std::filesystem::create_directories(dir.file("empty"));
  EXPECT_NE(error_text([&] { read_albedo_textures(dir.file("empty")); }).find("holds no .exr file"), std::string::npos);
}

TEST(AlbedoTexture, SynthPaintsTheTextureInTheSkinsColourAndLeavesThePapersSamplesAlone) {
  FACETOOL_REQUIRE_SHARED(testing::ict_face_model_dir());
  FACETOOL_REQUIRE_SHARED(testing::hdri_dir());
  FaceSource faces;
  faces.model = std::make_shared<const FaceModel>(FaceModel::load(testing::ict_face_model_dir()));
  SynthSettings settings;
  settings.camera.width = settings.camera.height = 48;
  settings.direction_count = 16;
  auto generator = [&](const SynthSettings& s) {
    return SampleGenerator(faces, load_light_sources({testing::hdri_dir()}), BackgroundSource(),
                           make_reference_renderer(), s);
  };
  // One texture of a single colour, seen everywhere.
  AlbedoTexture flat;
  flat.frame = albedo_texture_frame(faces.model->neutral(), 16);
  flat.rgb.assign(3 * 16 * 16, 0.0f);
  for (int c = 0; c < 3; ++c) std::fill(flat.rgb.begin() + c * 256, flat.rgb.begin() + (c + 1) * 256, 0.2f + 0.15f * c);
  flat.weight.assign(256, 1.0f);
  flat.source = "flat.exr";
  SynthSettings painted = settings;
  painted.albedo_textures = std::make_shared<const std::vector<AlbedoTexture>>(std::vector<AlbedoTexture>{flat});
  const SampleGenerator plain_generator = generator(settings);
  const SampleGenerator painted_generator = generator(painted);
  for (int64_t index = 0; index < 3; ++index) {
    const SynthSample a = plain_generator.generate(7, index);
    const SynthSample b = painted_generator.generate(7, index);
    // Everything but the albedo and the image drawn as without a texture.
    EXPECT_EQ(a.normal, b.normal);
    EXPECT_EQ(a.visibility, b.visibility);
    // The light is the same up to the exposure (scaled so the brightest face pixel hits its target).
    const double scale = b.light[0] / a.light[0];
    for (size_t k = 0; k < a.light.size(); ++k) EXPECT_NEAR(b.light[k], scale * a.light[k], 1e-5 * std::abs(b.light[0]));
    EXPECT_EQ(a.albedo_texture, "");
    // "flat.exr mirror M gain R G B": every skin pixel is gain x colour (clamped), which is the
    // procedural skin colour the sample drew.
    std::istringstream record(b.albedo_texture);
    std::string source, mirror_word, gain_word;
    int mirror = -1;
    float gain[3] = {0, 0, 0};
    record >> source >> mirror_word >> mirror >> gain_word >> gain[0] >> gain[1] >> gain[2];
    ASSERT_FALSE(record.fail()) << b.albedo_texture;
    EXPECT_EQ(source, "flat.exr");
    const size_t plane = b.plane();
    int skin = 0, masked = 0;
    for (size_t p = 0; p < plane; ++p) {
      if (b.mask[p] < 0.5f) continue;
      ++masked;
      bool same = true;
      for (int c = 0; c < 3; ++c)
        same = same && std::abs(b.albedo[c * plane + p] - std::min(1.0f, gain[c] * (0.2f + 0.15f * c))) < 1e-5f;
      skin += same;
    }
    // The mask also holds the eyes (procedural): at most a few percent of it.
    EXPECT_GT(skin, 0.9 * masked) << "sample " << index << ": " << skin << " of " << masked;
  }
  // Painting none of the samples gives the paper's samples, bit for bit.
  painted.albedo_texture_fraction = 0.0;
  const SynthSample a = plain_generator.generate(7, 1);
  const SynthSample b = generator(painted).generate(7, 1);
  EXPECT_EQ(a.image, b.image);
  EXPECT_EQ(a.albedo, b.albedo);
  EXPECT_EQ(b.albedo_texture, "");
}

}  // namespace
}  // namespace facetool
