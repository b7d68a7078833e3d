// ICT Face Model samples: the kept parts, label ranges, the light's scale, and re-rendering the
// stored components reproducing the stored image (needs ../shared; skips without it).
#include <algorithm>
#include <cmath>

#include "libs/io/exr_io.h"
#include "core/sh/light_clamp.h"
#include "libs/synth/gbuffer.h"
#include "libs/synth/sample_generator.h"
#include "core/util/error.h"
#include "synth_test_support.h"
#include "core/util/math_constants.h"

namespace facetool {
namespace {

class FaceSamples : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (testing::ict_face_model_dir().empty() || testing::hdri_dir().empty()) return;
    model = std::make_shared<const FaceModel>(FaceModel::load(testing::ict_face_model_dir()));
    SynthSettings settings;
    settings.camera.width = settings.camera.height = 64;
    settings.direction_count = 300;
    FaceSource faces;
    faces.model = model;
    generator = new SampleGenerator(faces, load_light_sources({testing::hdri_dir()}),
                                    BackgroundSource(), make_reference_renderer(), settings);
  }
  static void TearDownTestSuite() {
    delete generator;
    generator = nullptr;
  }
  void SetUp() override {
    FACETOOL_REQUIRE_SHARED(testing::ict_face_model_dir());
    FACETOOL_REQUIRE_SHARED(testing::hdri_dir());
  }
  static std::shared_ptr<const FaceModel> model;
  static SampleGenerator* generator;
};
std::shared_ptr<const FaceModel> FaceSamples::model;
SampleGenerator* FaceSamples::generator = nullptr;

TEST_F(FaceSamples, ModelKeepsTheHeadAndDropsTheMouthInteriorAndEyeOverlays) {
  EXPECT_EQ(model->identity_count(), 60);
  // 53 ARKit-style shapes + cheekRaiser_L/R + PupilDilate_L/R.
  EXPECT_EQ(model->expression_names().size(), 57u);
  EXPECT_EQ(model->landmarks().size(), 68u);
  int counts[16] = {};
  for (FacePart part : model->neutral().triangle_parts) ++counts[static_cast<int>(part)];
  for (FacePart dropped : {FacePart::kMouthSocket, FacePart::kGumsTongue, FacePart::kTeeth,
                           FacePart::kEyeOverlay, FacePart::kCornea})
    EXPECT_EQ(counts[static_cast<int>(dropped)], 0) << face_part_name(dropped);
  for (FacePart kept : {FacePart::kFace, FacePart::kHeadNeck, FacePart::kEyeSocket,
                        FacePart::kSclera, FacePart::kIris})
    EXPECT_GT(counts[static_cast<int>(kept)], 100) << face_part_name(kept);
  for (int32_t v : model->landmarks()) EXPECT_GE(v, 0);
}

TEST_F(FaceSamples, LabelsAreInRangeAndTheLightIsScaledAsThePaper) {
  for (int index = 0; index < 3; ++index) {
    const SynthSample s = generator->generate(3, index);
    const size_t plane = s.plane();
    float peak = 0;
    int inside = 0;
    for (size_t p = 0; p < plane; ++p) {
      if (s.mask[p] == 0.0f) continue;
      ++inside;
      const double n = std::sqrt(s.normal[p] * s.normal[p] + s.normal[plane + p] * s.normal[plane + p] +
                                 s.normal[2 * plane + p] * s.normal[2 * plane + p]);
      EXPECT_NEAR(n, 1.0, 1e-4);
      for (int c = 0; c < 3; ++c) {
        EXPECT_GE(s.albedo[c * plane + p], 0.0f);
        EXPECT_LE(s.albedo[c * plane + p], 1.0f);
        peak = std::max(peak, s.image[c * plane + p]);
      }
      // v_0 lies between 0 (closed) and sqrt(pi) (open hemisphere), the latter up to the
      // sampling error of 300 directions (a horizon can cut a few more than half of them).
      EXPECT_GE(s.visibility[p], 0.0f);
      EXPECT_LE(s.visibility[p], 1.05f * std::sqrt(static_cast<float>(kPi)));
      EXPECT_GT(s.depth[p], 3.5f);
      EXPECT_LT(s.depth[p], 8.5f);
    }
    EXPECT_GT(inside, 500) << "the head should fill a good part of the image";
    EXPECT_GE(peak, 0.8f - 1e-5f);
    EXPECT_LE(peak, 1.0f + 1e-5f);
    for (int c = 0; c < 3; ++c) EXPECT_GE(sh::min_radiance(sh::light_channel(s.light, c), 4000), -1e-6);
    EXPECT_GE(std::fabs(s.pose.roll_deg), 0.0);
    EXPECT_LE(std::fabs(s.pose.roll_deg), 30.0);
    EXPECT_LE(std::fabs(s.pose.pitch_deg), 20.0);
    EXPECT_LE(std::fabs(s.pose.yaw_deg), 30.0);
    EXPECT_GE(s.fov_deg, 20.0);
    EXPECT_LE(s.fov_deg, 25.0);
  }
}

TEST_F(FaceSamples, ReRenderingStoredComponentsReproducesTheStoredImage) {
  testing::ScratchDir dir("synth-face");
  const SynthSample generated = generator->generate(9, 4);
  write_synth_sample(dir.file("s.exr"), generated);
  const SynthSample stored = read_synth_sample(dir.file("s.exr"));
  EXPECT_EQ(stored.light, generated.light);  // 27 coefficients survive the metadata exactly
  EXPECT_EQ(stored.image, generated.image);  // float channels are stored losslessly
  const size_t plane = stored.plane();
  std::vector<int> masked;
  for (size_t p = 0; p < plane; ++p)
    if (stored.mask[p] > 0.5f) masked.push_back(static_cast<int>(p));
  const int n = static_cast<int>(masked.size());
  std::vector<float> albedo(3 * n), normal(3 * n), visibility(9 * n), image(3 * n);
  for (int k = 0; k < n; ++k) {
    for (int c = 0; c < 3; ++c) {
      albedo[c * n + k] = stored.albedo[c * plane + masked[k]];
      normal[c * n + k] = stored.normal[c * plane + masked[k]];
    }
    for (int i = 0; i < 9; ++i) visibility[i * n + k] = stored.visibility[i * plane + masked[k]];
  }
  make_reference_renderer()->render(n, albedo.data(), normal.data(), visibility.data(),
                                    stored.light, image.data());
  double worst = 0;
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, static_cast<double>(std::fabs(image[c * n + k] - stored.image[c * plane + masked[k]])));
  EXPECT_LT(worst, 1e-6);
}

TEST_F(FaceSamples, MaskIsTheFaceRegionAndTheHeadAroundItIsStillRendered) {
  const SynthSample s = generator->generate(5, 1);
  const size_t plane = s.plane();
  int face = 0, head_outside_face = 0;
  for (size_t p = 0; p < plane; ++p) {
    face += s.mask[p] > 0.5f;
    if (s.depth[p] > 0.0f && s.mask[p] == 0.0f) {
      ++head_outside_face;
      EXPECT_GT(s.albedo[p] + s.albedo[plane + p] + s.albedo[2 * plane + p], 0.0f);
    }
    if (s.mask[p] > 0.5f) {
      EXPECT_GT(s.depth[p], 0.0f) << "the mask lies on the head";
    }
  }
  EXPECT_GT(face, 500);
  EXPECT_GT(head_outside_face, 50) << "ears, neck or hair line should show around the face";
}

TEST_F(FaceSamples, VisibilityIsZeroOutsideTheDilatedMaskAndUnchangedInsideIt) {
  SynthSettings settings = generator->settings();
  settings.visibility_on_whole_head = true;
  FaceSource faces;
  faces.model = model;
  const SampleGenerator full_generator(faces, generator->lights(), BackgroundSource(),
                                       make_reference_renderer(), settings);
  for (int index = 0; index < 2; ++index) {
    const SynthSample s = generator->generate(17, index), full = full_generator.generate(17, index);
    const size_t plane = s.plane();
    ASSERT_EQ(s.mask, full.mask);
    std::vector<uint8_t> mask(plane);
    for (size_t p = 0; p < plane; ++p) mask[p] = s.mask[p] > 0.5f;
    const std::vector<uint8_t> dilated = dilate_mask(mask, s.width, s.height);
    int inside = 0, outside_head = 0, differing = 0;
    double worst = 0;
    for (size_t p = 0; p < plane; ++p) {
      const bool head = s.depth[p] > 0.0f;
      if (!dilated[p]) {
        for (int i = 0; i < 9; ++i) ASSERT_EQ(s.visibility[i * plane + p], 0.0f) << "pixel " << p;
        if (head && full.visibility[p] > 0.1f) ++outside_head;  // the full run did cast there
        continue;
      }
      if (!head) continue;
      ++inside;
      double error = 0;
      for (int i = 0; i < 9; ++i)
        error = std::max(error, static_cast<double>(std::fabs(s.visibility[i * plane + p] -
                                                              full.visibility[i * plane + p])));
      worst = std::max(worst, error);
      differing += error > 1e-5;
    }
    EXPECT_GT(inside, 500);
    EXPECT_GT(outside_head, 20) << "the comparison should cover head pixels left out";
    // Same rays, grouped into other packets: equal up to Embree's rounding of a rare grazing ray
    // (one ray of 300 directions moves a coefficient by at most 4 pi / 300 * 0.55 = 0.023).
    EXPECT_LT(worst, 0.05);
    EXPECT_LE(differing, inside / 100) << "worst " << worst;
  }
}

TEST_F(FaceSamples, FixedExpressionsOverrideTheRandomOnesAndUnknownNamesAreErrors) {
  // Same random stream with and without fixed expressions: the identity and every other
  // expression weight are the same; the fixed ones hold exactly their weight.
  ShapeSampling random_only, closed = random_only;
  closed.fixed_expressions = {{"eyeBlink_L", 1.0}, {"eyeBlink_R", 0.5}};
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    Random a(seed), b(seed);
    const ShapeWeights plain = model->sample(a, random_only), fixed = model->sample(b, closed);
    EXPECT_EQ(plain.identity, fixed.identity);
    const std::vector<std::string>& names = model->expression_names();
    for (size_t k = 0; k < names.size(); ++k) {
      if (names[k] == "eyeBlink_L") EXPECT_EQ(fixed.expression[k], 1.0f);
      else if (names[k] == "eyeBlink_R") EXPECT_EQ(fixed.expression[k], 0.5f);
      else EXPECT_EQ(fixed.expression[k], plain.expression[k]) << names[k];
    }
  }
  ShapeSampling unknown;
  unknown.fixed_expressions = {{"noSuchShape", 1.0}};
  Random r(1);
  try {
    model->sample(r, unknown);
    ADD_FAILURE() << "an unknown expression name was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("noSuchShape"), std::string::npos) << e.what();
  }
}

TEST_F(FaceSamples, SameSeedSameSampleDifferentSeedDifferentSample) {
  const SynthSample a = generator->generate(21, 2), b = generator->generate(21, 2),
                    c = generator->generate(21, 3);
  EXPECT_EQ(a.image, b.image);
  EXPECT_EQ(a.visibility, b.visibility);
  EXPECT_NE(a.image, c.image);
}

}  // namespace
}  // namespace facetool
