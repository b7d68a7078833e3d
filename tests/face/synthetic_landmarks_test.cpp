// dlib's landmarks on rendered synthetic faces, whose 68 landmark positions are known exactly
// from the mesh: mean error of the 51 inner points and of the jaw line, as a fraction of the
// inter-ocular distance (outer eye corners 36-45, the 300-W convention).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "libs/face/face_detector.h"
#include "libs/synth/component_renderer.h"
#include "libs/synth/face_model.h"
#include "libs/synth/light_source.h"
#include "libs/synth/random.h"
#include "libs/synth/sample_generator.h"
#include "core/util/math_constants.h"

namespace facetool {
namespace {

// Mirrors SampleGenerator::generate's sub-streams (libs/synth/sample_generator.cpp): the shape
// comes from stream 1, the pose from stream 3. The depth check below fails if they drift apart.
constexpr uint64_t kShapeStream = 1, kPoseStream = 3;

struct Errors {
  double inner = 0, jaw = 0;  // mean point error / inter-ocular distance
  double brows = 0, nose = 0, eyes = 0, mouth = 0;  // the inner points by part
  bool detected = false;
  std::string detector, landmark_box;  // the first face's (DetectedFace)
};

// How a run renders and detects: eyes closed (ICT eyeBlink_L/R at 1), the background made nearly
// black, and the detection options.
struct Variant {
  bool closed_eyes = false, dark_background = false;
  DetectionOptions options;
};

class SyntheticLandmarks : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const std::string shared = FACETOOL_SHARED_DIR;
    const std::string face_model = shared + "/assets/ict-facekit/FaceXModel", hdri = shared + "/assets/hdri";
    if (!std::filesystem::exists(face_model) || !std::filesystem::exists(hdri) ||
        !std::filesystem::exists(kDefaultLandmarkModel))
      return;
    model_ = std::make_shared<const FaceModel>(FaceModel::load(face_model));
    lights_ = load_light_sources({hdri});
    detector_ = std::make_unique<FaceDetector>();
  }
  static void TearDownTestSuite() {
    detector_.reset();
    model_.reset();
    lights_.clear();
  }
  void SetUp() override {
    if (!model_) GTEST_SKIP() << "needs ../shared (ICT face model, HDRIs) and dlib's landmark model";
  }

  static SynthSettings settings(double max_yaw, bool closed_eyes = false) {
    SynthSettings s;
    if (closed_eyes) s.shape.fixed_expressions = {{"eyeBlink_L", 1.0}, {"eyeBlink_R", 1.0}};
    s.camera.width = s.camera.height = 256;
    s.direction_count = 48;  // visibility only shades the image; few directions suffice here
    s.pose.max_roll_deg = 10;
    s.pose.max_pitch_deg = 10;
    s.pose.max_yaw_deg = max_yaw;
    return s;
  }

  // A rendered sample and its 68 landmark positions projected from the mesh.
  struct Render {
    RgbImage image;
    Landmarks68 truth;
  };

  // Renders sample `index` and projects its landmark vertices.
  static Render render(const SampleGenerator& generator, uint64_t seed, int64_t index, const Variant& variant) {
    const SynthSample s = generator.generate(seed, index);
    Random shape_random(derive_seed(s.sample_seed, kShapeStream));
    FaceMesh mesh = model_->build(model_->sample(shape_random, generator.settings().shape));
    apply_pose(mesh, s.pose);
    Camera camera;
    camera.width = s.width;
    camera.height = s.height;
    camera.horizontal_fov_deg = s.fov_deg;
    const double half = std::tan(0.5 * s.fov_deg * kPi / 180);
    Render r;
    for (int i = 0; i < kLandmarkCount; ++i) {
      const Vec3f p = mesh.positions[model_->landmarks()[i]];
      const double depth = camera.distance - p.z;
      r.truth[i] = {(p.x / depth / half + 1) * 0.5 * s.width - 0.5, (1 - p.y / depth / half) * 0.5 * s.height - 0.5};
      if (i == 30) {  // the nose tip is visible: the rendered depth there must match the mesh
        const int x = static_cast<int>(std::lround(r.truth[i].x)), y = static_cast<int>(std::lround(r.truth[i].y));
        EXPECT_NEAR(s.depth[static_cast<size_t>(y) * s.width + x], depth, 0.02)
            << "the test's copy of the shape and pose no longer matches the generator's";
      }
    }
    r.image.width = s.width;
    r.image.height = s.height;
    r.image.pixels.resize(s.plane() * 3);
    for (size_t p = 0; p < s.plane(); ++p)
      for (int c = 0; c < 3; ++c)
        r.image.pixels[p * 3 + c] = variant.dark_background && s.depth[p] == 0 ? 0.002f : s.image[c * s.plane() + p];
    return r;
  }

  // Runs the detector on a render and compares the first face's points with the truth.
  static Errors evaluate(const Render& r, const DetectionOptions& detection) {
    DetectionOptions options = detection;
    options.min_face_size = 60;
    const std::vector<DetectedFace> faces = detector_->detect(r.image, options);
    Errors e;
    if (faces.empty()) return e;
    e.detected = true;
    e.detector = faces[0].detector;
    e.landmark_box = faces[0].landmark_box;
    const Landmarks68& truth = r.truth;
    const double iod = std::hypot(truth[36].x - truth[45].x, truth[36].y - truth[45].y);
    for (int i = 0; i < kLandmarkCount; ++i) {
      const double d = std::hypot(faces[0].landmarks[i].x - truth[i].x, faces[0].landmarks[i].y - truth[i].y) / iod;
      (is_inner_landmark(i) ? e.inner : e.jaw) += d;
      (i >= 48 ? e.mouth : i >= 36 ? e.eyes : i >= 27 ? e.nose : e.brows) += i >= 17 ? d : 0;
    }
    e.inner /= 51;
    e.jaw /= 17;
    e.brows /= 10;
    e.nose /= 9;
    e.eyes /= 12;
    e.mouth /= 20;
    return e;
  }

  static Errors measure(const SampleGenerator& generator, uint64_t seed, int64_t index, const Variant& variant) {
    return evaluate(render(generator, seed, index, variant), variant.options);
  }

  // The indices of the first `count` samples whose |yaw| is in [low, high] (from the pose stream).
  static std::vector<int64_t> samples_in_yaw_range(const SampleGenerator& generator, uint64_t seed, double low,
                                                   double high, int count) {
    std::vector<int64_t> indices;
    for (int64_t index = 0; static_cast<int>(indices.size()) < count && index < 2000; ++index) {
      Random pose_random(derive_seed(derive_seed(seed, static_cast<uint64_t>(index)), kPoseStream));
      const HeadPose pose = sample_pose(pose_random, generator.settings().pose);
      if (std::abs(pose.yaw_deg) >= low && std::abs(pose.yaw_deg) <= high) indices.push_back(index);
    }
    return indices;
  }

  // Mean errors over `count` samples whose |yaw| is in [low, high] (chosen from the pose stream).
  static void run(double low, double high, int count, Errors& mean, int& detected,
                  const Variant& variant = Variant()) {
    const uint64_t seed = 11;
    const SampleGenerator generator({model_, nullptr}, lights_, BackgroundSource(),
                                    make_reference_renderer(), settings(high, variant.closed_eyes));
    detected = 0;
    for (int64_t index : samples_in_yaw_range(generator, seed, low, high, count)) {
      const Errors e = measure(generator, seed, index, variant);
      if (!e.detected) continue;
      ++detected;
      mean.inner += e.inner;
      mean.jaw += e.jaw;
    }
    if (detected > 0) {
      mean.inner /= detected;
      mean.jaw /= detected;
    }
  }

  static std::shared_ptr<const FaceModel> model_;
  static std::vector<LightSource> lights_;
  static std::unique_ptr<FaceDetector> detector_;
};
std::shared_ptr<const FaceModel> SyntheticLandmarks::model_;
std::vector<LightSource> SyntheticLandmarks::lights_;
std::unique_ptr<FaceDetector> SyntheticLandmarks::detector_;

TEST_F(SyntheticLandmarks, NearFrontalInnerPointsWithinFivePercentOfTheInterOcularDistance) {
  Errors mean;
  int detected = 0;
  run(0, 10, 8, mean, detected);
  std::printf("near-frontal (|yaw| <= 10): %d of 8 detected; inner points %.2f %% IOD, jaw %.2f %% IOD\n",
              detected, 100 * mean.inner, 100 * mean.jaw);
  ASSERT_GE(detected, 6);
  EXPECT_LT(mean.inner, 0.05);
  EXPECT_LT(mean.jaw, 0.15);  // contours: a looser stated bound (measured 3.5 % and 7.4 %)
}

TEST_F(SyntheticLandmarks, ThirtyDegreesYaw) {
  Errors mean;
  int detected = 0;
  run(25, 30, 8, mean, detected);
  std::printf("yaw 25-30 degrees: %d of 8 detected; inner points %.2f %% IOD, jaw %.2f %% IOD\n",
              detected, 100 * mean.inner, 100 * mean.jaw);
  ASSERT_GE(detected, 4);
  EXPECT_LT(mean.inner, 0.08);  // measured 5.3 % inner, 15.3 % jaw, 8 of 8 detected
  EXPECT_LT(mean.jaw, 0.25);
}

TEST_F(SyntheticLandmarks, ClosedEyesOnADarkBackgroundAreFound) {
  // The case dlib's HOG detector alone missed most of: closed eyes, black background, turned.
  Variant variant;
  variant.closed_eyes = variant.dark_background = true;
  Errors mean;
  int detected = 0;
  run(0, 45, 8, mean, detected, variant);
  std::printf("closed eyes, dark background, |yaw| <= 45: %d of 8 detected; inner points %.2f %% IOD\n",
              detected, 100 * mean.inner);
  EXPECT_GE(detected, 7);
  // Measured 8 of 8, inner 15.1 % IOD (11.7 % with 40 pixels of padding instead of 64: the
  // points move with the box); up to 45 degrees of yaw with the eyelids closed the predictor
  // places the points poorly. A stated bound with some room.
  EXPECT_LT(mean.inner, 0.20);
}

TEST_F(SyntheticLandmarks, DisagreeingMirroredFitsAreRetriedInOtherBoxes) {
  // Turned faces are where the fit and the mirrored fit disagree most. On the renders of the
  // measurement in docs/photos.md ("Landmark agreement"), retrying them in six other boxes and
  // keeping the most self-consistent pair must change some faces' points and bring them closer
  // to the truth on average (measured: 2 of 12 faces retried, 5.00 % -> 4.61 % of the
  // inter-ocular distance).
  const uint64_t seed = 11;
  const SampleGenerator generator({model_, nullptr}, lights_, BackgroundSource(), make_reference_renderer(),
                                  settings(30));
  DetectionOptions never;
  never.landmark_retry_disagreement = -1;
  const DetectionOptions by_default;
  double sum_never = 0, sum_default = 0;
  int both = 0, changed = 0;
  for (int64_t index : samples_in_yaw_range(generator, seed, 15, 30, 12)) {
    const Render r = render(generator, seed, index, Variant());
    const Errors a = evaluate(r, never), b = evaluate(r, by_default);
    if (!a.detected || !b.detected) continue;
    ++both;
    sum_never += a.inner;
    sum_default += b.inner;
    changed += a.inner != b.inner;
  }
  std::printf("|yaw| 15-30: %d faces, %d retried; inner points %.2f %% IOD never retried, %.2f %% by default\n", both,
              changed, 100 * sum_never / std::max(both, 1), 100 * sum_default / std::max(both, 1));
  ASSERT_GE(both, 10);
  EXPECT_GE(changed, 1);
  EXPECT_LT(sum_default, sum_never);
}

TEST_F(SyntheticLandmarks, TurnedFacesOnlyTheCnnFindsAreFittedInHogsBox) {
  // At 15-30 degrees of yaw HOG misses some faces (its score below the threshold) and the CNN
  // finds them; the landmark model, trained on HOG's boxes, places their points far off in the
  // mapped CNN box. HOG's box for them at a lower margin (DetectionOptions::hog_box_for_cnn_faces)
  // must be used for some and bring their points closer to the truth on average (measured: 4 such
  // faces in these 24 renders, all 4 in HOG's box, 5.05 % -> 4.22 % of the inter-ocular distance;
  // in 48 renders 7 faces, 12.0 % -> 4.8 %: docs/photos.md).
  const uint64_t seed = 11;
  const SampleGenerator generator({model_, nullptr}, lights_, BackgroundSource(), make_reference_renderer(),
                                  settings(30));
  DetectionOptions hog_only, off;
  hog_only.detector = DetectorChoice::hog;
  off.hog_box_for_cnn_faces = false;
  const DetectionOptions by_default;
  double sum_off = 0, sum_default = 0;
  int cnn_faces = 0, in_hog_box = 0;
  for (int64_t index : samples_in_yaw_range(generator, seed, 15, 30, 24)) {
    const Render r = render(generator, seed, index, Variant());
    if (evaluate(r, hog_only).detected) continue;  // HOG finds it: the option does not apply
    const Errors a = evaluate(r, off), b = evaluate(r, by_default);
    if (!a.detected || !b.detected) continue;
    EXPECT_EQ(a.detector, "cnn");
    EXPECT_EQ(a.landmark_box, "cnn");
    ++cnn_faces;
    in_hog_box += b.landmark_box == "hog";
    sum_off += a.inner;
    sum_default += b.inner;
  }
  std::printf("|yaw| 15-30: %d faces only the CNN found, %d fitted in HOG's box; inner points %.2f %% IOD in the "
              "mapped CNN box, %.2f %% by default\n", cnn_faces, in_hog_box, 100 * sum_off / std::max(cnn_faces, 1),
              100 * sum_default / std::max(cnn_faces, 1));
  ASSERT_GE(cnn_faces, 2);
  EXPECT_GE(in_hog_box, 1);
  EXPECT_LT(sum_default, sum_off);
  EXPECT_LT(sum_default / cnn_faces, 0.08);  // a stated bound: the HOG-found faces' 4.8 % with room
}

// The figures of docs/photos.md ("Landmark boxes", closed eyes): per detector and box mapping,
// detection rate and landmark error over yaw ranges. A measurement, not a check: run with
// --gtest_also_run_disabled_tests (about 15 minutes on 2 busy cores).
TEST_F(SyntheticLandmarks, DISABLED_MeasureDetectorsAndBoxConventions) {
  struct Named {
    const char* name;
    Variant variant;
  };
  std::vector<Named> variants(5);
  variants[0].name = "hog";
  variants[0].variant.options.detector = DetectorChoice::hog;
  variants[1].name = "cnn, its own box";
  variants[1].variant.options.detector = DetectorChoice::cnn;
  variants[1].variant.options.map_cnn_boxes = false;
  variants[2].name = "cnn, box mapped to HOG's";
  variants[2].variant.options.detector = DetectorChoice::cnn;
  variants[3].name = "cnn, mapped, refit from landmarks";
  variants[3].variant.options.detector = DetectorChoice::cnn;
  variants[3].variant.options.refit_landmarks = true;
  variants[4].name = "hog, refit from landmarks";
  variants[4].variant.options.detector = DetectorChoice::hog;
  variants[4].variant.options.refit_landmarks = true;
  // The table was measured with one plain landmark fit in the box (before the mirrored fit on a
  // scaled chip became the default) and the CNN's faces in their own or mapped box (before HOG's
  // box for them): keep that, so the test reproduces it.
  for (Named& v : variants) {
    v.variant.options.mirror_landmarks = false;
    v.variant.options.landmark_box_pixels = 0;
    v.variant.options.hog_box_for_cnn_faces = false;
  }
  const int count = 8;
  for (const Named& v : variants)
    for (const auto& [low, high] : std::vector<std::pair<double, double>>{{0, 15}, {15, 30}}) {
      Errors mean;
      int detected = 0;
      run(low, high, count, mean, detected, v.variant);
      std::printf("%-34s |yaw| %2.0f-%2.0f: %2d of %d, inner %.2f %% IOD, jaw %.2f %% IOD\n", v.name, low,
                  high, detected, count, 100 * mean.inner, 100 * mean.jaw);
      std::fflush(stdout);
    }
  for (DetectorChoice choice : {DetectorChoice::hog, DetectorChoice::cnn, DetectorChoice::automatic}) {
    Variant closed;
    closed.closed_eyes = closed.dark_background = true;
    closed.options.detector = choice;
    closed.options.mirror_landmarks = false;
    closed.options.landmark_box_pixels = 0;
    closed.options.hog_box_for_cnn_faces = false;
    for (const auto& [low, high] : std::vector<std::pair<double, double>>{{0, 25}, {25, 45}}) {
      Errors mean;
      int detected = 0;
      run(low, high, 12, mean, detected, closed);
      std::printf("closed eyes, dark, %-4s |yaw| %2.0f-%2.0f: %2d of 12, inner %.2f %% IOD\n",
                  detector_choice_name(choice), low, high, detected, 100 * mean.inner);
      std::fflush(stdout);
    }
  }
}

// The figures of docs/photos.md ("Landmark fit"): ways of fitting the landmarks in the same
// boxes, on the same renders (each rendered once): one plain fit, test-time mirroring, a chip
// scaled to a 200-pixel box (sub-pixel points), per detector and |yaw| range, with the landmark
// time per face. A measurement, not a check: run with --gtest_also_run_disabled_tests.
TEST_F(SyntheticLandmarks, DISABLED_MeasureLandmarkFitVariants) {
  struct Named {
    std::string name;
    DetectionOptions options;
  };
  std::vector<Named> variants;
  for (DetectorChoice choice : {DetectorChoice::hog, DetectorChoice::automatic})
    for (int k = 0; k < 4; ++k) {
      Named v;
      v.options.detector = choice;
      v.options.mirror_landmarks = k == 1 || k == 3;
      v.options.landmark_box_pixels = k >= 2 ? 200 : 0;
      v.options.hog_box_for_cnn_faces = false;  // as the table was measured (before that default)
      v.name = std::string(detector_choice_name(choice)) + (k == 0 ? ", one plain fit" : "") +
               (v.options.mirror_landmarks ? ", mirrored" : "") + (k >= 2 ? ", chip >= 200 px" : "") +
               (k == 3 ? " (the default before HOG's box for the CNN's faces)" : "");
      variants.push_back(v);
    }
  const int count = 12;
  const uint64_t seed = 11;
  for (const auto& [low, high] : std::vector<std::pair<double, double>>{{0, 15}, {15, 30}}) {
    const SampleGenerator generator({model_, nullptr}, lights_, BackgroundSource(),
                                    make_reference_renderer(), settings(high));
    std::vector<Render> renders;
    for (int64_t index : samples_in_yaw_range(generator, seed, low, high, count))
      renders.push_back(render(generator, seed, index, Variant()));
    for (const Named& v : variants) {
      Errors mean;
      int detected = 0;
      double landmark_seconds = 0;
      for (const Render& r : renders) {
        const Errors e = evaluate(r, v.options);
        if (!e.detected) continue;
        ++detected;
        landmark_seconds += detector_->last_landmark_seconds();
        mean.inner += e.inner;
        mean.jaw += e.jaw;
        mean.brows += e.brows;
        mean.nose += e.nose;
        mean.eyes += e.eyes;
        mean.mouth += e.mouth;
      }
      const double n = std::max(detected, 1);
      std::printf("%-36s |yaw| %2.0f-%2.0f: %2d of %zu, inner %.2f %% IOD (brows %.1f, nose %.1f, eyes %.1f, "
                  "mouth %.1f), jaw %.2f %% IOD, landmarks %.1f ms/face\n",
                  v.name.c_str(), low, high, detected, renders.size(), 100 * mean.inner / n, 100 * mean.brows / n,
                  100 * mean.nose / n, 100 * mean.eyes / n, 100 * mean.mouth / n, 100 * mean.jaw / n,
                  1000 * landmark_seconds / n);
      std::fflush(stdout);
    }
  }
}


// The figures of docs/photos.md ("Landmark boxes", faces only the CNN finds): the landmark error
// with and without HOG's box for them, per yaw range, with open eyes and closed on a dark
// background. A measurement, not a check: run with --gtest_also_run_disabled_tests (about 10
// minutes on 2 cores).
TEST_F(SyntheticLandmarks, DISABLED_MeasureHogBoxForCnnFaces) {
  const uint64_t seed = 11;
  struct Range {
    double low, high;
    bool closed;
    int count;
  };
  for (const Range& range : std::vector<Range>{{0, 15, false, 48}, {15, 30, false, 48}, {30, 45, false, 32},
                                               {0, 25, true, 24}, {25, 45, true, 24}}) {
    Variant variant;
    variant.closed_eyes = variant.dark_background = range.closed;
    const SampleGenerator generator({model_, nullptr}, lights_, BackgroundSource(), make_reference_renderer(),
                                    settings(range.high, range.closed));
    for (bool on : {false, true}) {
      DetectionOptions options;
      options.hog_box_for_cnn_faces = on;
      double all = 0, cnn = 0;
      int found = 0, cnn_faces = 0, in_hog_box = 0, rendered = 0;
      for (int64_t index : samples_in_yaw_range(generator, seed, range.low, range.high, range.count)) {
        ++rendered;
        const Errors e = evaluate(render(generator, seed, index, variant), options);
        if (!e.detected) continue;
        ++found;
        all += e.inner;
        if (e.detector != "cnn") continue;
        ++cnn_faces;
        cnn += e.inner;
        in_hog_box += e.landmark_box == "hog";
      }
      std::printf("%s|yaw| %2.0f-%2.0f, HOG's box for the CNN's faces %-3s: %d of %d found, inner %.2f %% IOD; "
                  "the CNN's %d faces %.2f %% (%d in HOG's box)\n",
                  range.closed ? "closed eyes, dark, " : "", range.low, range.high, on ? "on" : "off", found,
                  rendered, 100 * all / std::max(found, 1), cnn_faces, 100 * cnn / std::max(cnn_faces, 1),
                  in_hog_box);
      std::fflush(stdout);
    }
  }
}

}  // namespace
}  // namespace facetool
