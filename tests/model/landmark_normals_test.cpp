// The landmark normal head: its ridge fit against a plain solver, its prediction, rotation, blending and file form.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "core/util/error.h"
#include "libs/model/landmark_normals.h"
#include "libs/model/safetensors.h"

namespace facetool {
namespace {

constexpr int kSize = 12, kGrid = 4, kCells = kGrid * kGrid;
constexpr int kPoints = 2 * LandmarkNormals::kLandmarks;

// A mean face: points spread over the crop (the values matter only as a shape).
std::vector<float> mean_face() {
  std::vector<float> m(kPoints);
  for (int i = 0; i < LandmarkNormals::kLandmarks; ++i) {
    m[2 * i] = static_cast<float>(6.0 + 4.0 * std::cos(0.37 * i));
    m[2 * i + 1] = static_cast<float>(6.0 + 3.0 * std::sin(0.53 * i + 0.2 * (i % 5)));
  }
  return m;
}

// A face whose inner points are the mean's exactly (so its similarity onto the mean is the
// identity) and whose jaw points (0-16) move.
std::vector<float> jaw_face(const std::vector<float>& mean, std::mt19937& rng) {
  std::normal_distribution<float> noise(0.0f, 0.8f);
  std::vector<float> f = mean;
  for (int k = 0; k < 2 * 17; ++k) f[k] += noise(rng);
  return f;
}

// The features written out again, independently of LandmarkNormals::features.
std::vector<long double> plain_features(const std::vector<float>& xy) {
  std::vector<long double> f;
  for (float v : xy) f.push_back((v - kSize / 2.0L) / (kSize / 2.0L));
  for (float v : xy) f.push_back(std::pow((v - kSize / 2.0L) / (kSize / 2.0L), 2));
  f.push_back(1.0L);
  return f;
}

// Solves A x = b by Gaussian elimination with partial pivoting (long double).
std::vector<long double> gauss(std::vector<std::vector<long double>> a, std::vector<long double> b) {
  const size_t n = b.size();
  for (size_t c = 0; c < n; ++c) {
    size_t pivot = c;
    for (size_t r = c + 1; r < n; ++r)
      if (std::fabs(a[r][c]) > std::fabs(a[pivot][c])) pivot = r;
    std::swap(a[c], a[pivot]);
    std::swap(b[c], b[pivot]);
    for (size_t r = c + 1; r < n; ++r) {
      const long double k = a[r][c] / a[c][c];
      for (size_t j = c; j < n; ++j) a[r][j] -= k * a[c][j];
      b[r] -= k * b[c];
    }
  }
  std::vector<long double> x(n);
  for (size_t i = n; i-- > 0;) {
    long double v = b[i];
    for (size_t j = i + 1; j < n; ++j) v -= a[i][j] * x[j];
    x[i] = v / a[i][i];
  }
  return x;
}

// Labels constant over each of the grid's cells: cell c of face k holds values[k][c][0..3]
// (normal x, y, z; the mask 1 or 0).
void cell_labels(const std::vector<std::array<float, 4>>& cells, std::vector<float>& normal, std::vector<float>& mask) {
  const int cell = kSize / kGrid;
  const size_t plane = kSize * kSize;
  normal.assign(3 * plane, 0.0f);
  mask.assign(plane, 0.0f);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const std::array<float, 4>& v = cells[(y / cell) * kGrid + x / cell];
      const size_t p = static_cast<size_t>(y) * kSize + x;
      for (int c = 0; c < 3; ++c) normal[c * plane + p] = v[c];
      mask[p] = v[3];
    }
}

TEST(LandmarkNormals, FitEqualsAPlainRidgeSolution) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  const std::vector<float> mean = mean_face();
  LandmarkNormalsFit fit(kSize, kGrid, mean);
  constexpr int kFaces = 60;
  constexpr double kLambda = 0.01;
  const int n = LandmarkNormals::kFeatures;
  std::vector<std::vector<long double>> gram(n, std::vector<long double>(n, 0.0L));
  std::vector<std::vector<long double>> moment(kCells * 4, std::vector<long double>(n, 0.0L));
  for (int k = 0; k < kFaces; ++k) {
    const std::vector<float> face = jaw_face(mean, rng);
    std::vector<std::array<float, 4>> cells(kCells);
    for (auto& c : cells) c = {value(rng), value(rng), value(rng), value(rng) > -0.6f ? 1.0f : 0.0f};
    std::vector<float> normal, mask;
    cell_labels(cells, normal, mask);
    fit.add(face.data(), normal.data(), mask.data());
    const std::vector<long double> f = plain_features(face);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) gram[i][j] += f[i] * f[j];
    for (int c = 0; c < kCells; ++c)
      for (int v = 0; v < 4; ++v) {
        // The cell's targets: the normal times the mask, and the mask.
        const long double target = v < 3 ? cells[c][v] * cells[c][3] : cells[c][3];
        for (int i = 0; i < n; ++i) moment[c * 4 + v][i] += f[i] * target;
      }
  }
  for (int i = 0; i < n; ++i) gram[i][i] += kLambda;
  const LandmarkNormals head = fit.solve(kLambda, 1.0f);
  ASSERT_EQ(head.weights.size(), static_cast<size_t>(n) * kCells * 4);
  EXPECT_EQ(head.mean_landmarks, mean);
  double worst = 0, largest = 0;
  for (int column = 0; column < kCells * 4; column += 5) {  // every fifth column, for time
    const std::vector<long double> w = gauss(gram, moment[column]);
    for (int i = 0; i < n; ++i) {
      worst = std::max(worst, static_cast<double>(std::fabs(head.weights[i * kCells * 4 + column] - w[i])));
      largest = std::max(largest, static_cast<double>(std::fabs(w[i])));
    }
  }
  EXPECT_LT(worst, 1e-5 * std::max(1.0, largest)) << "largest weight " << largest;
}

// A head fitted to faces whose labels are one constant normal each, linear in the features:
// it predicts that normal everywhere, and the mask 1.
LandmarkNormals constant_head(std::vector<std::vector<float>>& faces, std::vector<std::array<double, 3>>& truth) {
  std::mt19937 rng(11);
  const std::vector<float> mean = mean_face();
  LandmarkNormalsFit fit(kSize, kGrid, mean);
  for (int k = 0; k < 400; ++k) {
    faces.push_back(jaw_face(mean, rng));
    const std::vector<double> f = LandmarkNormals::features(faces.back().data(), kSize);
    const std::array<double, 3> n{0.3 + 0.2 * f[0], -0.2 + 0.1 * f[3] - 0.1 * f[136], 0.9};
    truth.push_back(n);
    std::vector<std::array<float, 4>> cells(kCells, {static_cast<float>(n[0]), static_cast<float>(n[1]),
                                                     static_cast<float>(n[2]), 1.0f});
    std::vector<float> normal, mask;
    cell_labels(cells, normal, mask);
    fit.add(faces.back().data(), normal.data(), mask.data());
  }
  return fit.solve(1e-9, 1.0f);
}

TEST(LandmarkNormals, PredictsTheNormalItLearnt) {
  std::vector<std::vector<float>> faces;
  std::vector<std::array<double, 3>> truth;
  const LandmarkNormals head = constant_head(faces, truth);
  for (int k : {0, 17, 399}) {
    std::vector<float> normal, mask;
    head.predict(faces[k].data(), normal, mask);
    const double length = std::sqrt(truth[k][0] * truth[k][0] + truth[k][1] * truth[k][1] + truth[k][2] * truth[k][2]);
    for (size_t p = 0; p < mask.size(); ++p) {
      ASSERT_NEAR(mask[p], 1.0, 1e-4);
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(normal[c * mask.size() + p], truth[k][c] / length, 1e-4) << k << " " << p;
    }
  }
}

TEST(LandmarkNormals, ARolledFaceGetsItsNormalsRolled) {
  std::vector<std::vector<float>> faces;
  std::vector<std::array<double, 3>> truth;
  const LandmarkNormals head = constant_head(faces, truth);
  // The face turned by 25 degrees about the crop's centre (image axes, y down), shifted and scaled.
  const double angle = 25.0 * M_PI / 180.0, c = std::cos(angle), s = std::sin(angle), scale = 0.9;
  std::vector<float> turned(kPoints);
  for (int i = 0; i < LandmarkNormals::kLandmarks; ++i) {
    const double x = faces[5][2 * i] - 6.0, y = faces[5][2 * i + 1] - 6.0;
    turned[2 * i] = static_cast<float>(6.3 + scale * (c * x - s * y));
    turned[2 * i + 1] = static_cast<float>(5.8 + scale * (s * x + c * y));
  }
  std::vector<float> normal, mask;
  head.predict(turned.data(), normal, mask);
  const auto& n = truth[5];
  const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  // The normal's image-axes vector (x, -y) turned like the face.
  const double ix = n[0] / length, iy = -n[1] / length;
  const double rx = c * ix - s * iy, ry = s * ix + c * iy;
  const size_t plane = mask.size();
  for (size_t p = 0; p < plane; ++p) {
    ASSERT_NEAR(normal[p], rx, 1e-3);
    ASSERT_NEAR(normal[plane + p], -ry, 1e-3);
    ASSERT_NEAR(normal[2 * plane + p], n[2] / length, 1e-3);
  }
}

TEST(LandmarkNormals, BlendWeighsTheHeadAgainstTheNetwork) {
  std::vector<std::vector<float>> faces;
  std::vector<std::array<double, 3>> truth;
  LandmarkNormals head = constant_head(faces, truth);
  const size_t plane = kSize * kSize;
  std::vector<float> head_normal, mask;
  head.predict(faces[3].data(), head_normal, mask);
  for (float blend : {1.0f, 0.5f, 0.0f}) {
    head.blend = blend;
    std::vector<float> normal(3 * plane, 0.0f);
    for (size_t p = 0; p < plane; ++p) normal[2 * plane + p] = 1.0f;  // the network: facing the camera
    head.blend_into(faces[3].data(), normal.data());
    for (size_t p = 0; p < plane; ++p) {
      double expected[3], length = 0;
      for (int c = 0; c < 3; ++c) {
        expected[c] = blend * head_normal[c * plane + p] + (1 - blend) * (c == 2 ? 1.0 : 0.0);
        length += expected[c] * expected[c];
      }
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(normal[c * plane + p], expected[c] / std::sqrt(length), 1e-5) << "blend " << blend;
    }
  }
  // Where the head's mask is 0 the network's normals stay.
  LandmarkNormalsFit fit(kSize, kGrid, mean_face());
  std::mt19937 rng(3);
  for (int k = 0; k < 300; ++k) {
    const std::vector<float> face = jaw_face(mean_face(), rng);
    std::vector<std::array<float, 4>> cells(kCells, {0.5f, 0.5f, 0.5f, 0.0f});
    std::vector<float> normal, m;
    cell_labels(cells, normal, m);
    fit.add(face.data(), normal.data(), m.data());
  }
  const LandmarkNormals empty = fit.solve(1e-6, 1.0f);
  std::vector<float> normal(3 * plane, 0.0f);
  for (size_t p = 0; p < plane; ++p) normal[p] = 1.0f;
  const std::vector<float> before = normal;
  empty.blend_into(faces[3].data(), normal.data());
  EXPECT_EQ(normal, before);
}

TEST(LandmarkNormals, WeightsFileRoundTripAndDamage) {
  std::vector<std::vector<float>> faces;
  std::vector<std::array<double, 3>> truth;
  LandmarkNormals head = constant_head(faces, truth);
  head.blend = 0.75f;
  const std::string path = (std::filesystem::temp_directory_path() / "landmark_normals_test.safetensors").string();
  {
    SafeTensorsWriter writer;
    writer.set_metadata("format", "anything");
    add_landmark_normals(writer, head);
    writer.write_file(path);
  }
  const auto back = read_landmark_normals(SafeTensors::read_file(path), path);
  ASSERT_NE(back, nullptr);
  EXPECT_EQ(back->crop_size, kSize);
  EXPECT_EQ(back->grid, kGrid);
  EXPECT_FLOAT_EQ(back->blend, 0.75f);
  EXPECT_EQ(back->weights, head.weights);
  EXPECT_EQ(back->mean_landmarks, head.mean_landmarks);
  EXPECT_TRUE(is_landmark_normals_tensor(kLandmarkNormalsTensor));
  EXPECT_TRUE(is_landmark_normals_tensor(kLandmarkNormalsMean));
  EXPECT_FALSE(is_landmark_normals_tensor("landmark_normals.other"));

  auto error_of = [&](const std::function<void(SafeTensorsWriter&)>& make) {
    SafeTensorsWriter writer;
    make(writer);
    writer.write_file(path);
    try {
      read_landmark_normals(SafeTensors::read_file(path), path);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // No head at all: null, no error.
  {
    SafeTensorsWriter writer;
    writer.add("x", {1}, {1.0f});
    writer.write_file(path);
    EXPECT_EQ(read_landmark_normals(SafeTensors::read_file(path), path), nullptr);
  }
  EXPECT_NE(error_of([&](SafeTensorsWriter& w) {
              w.add(kLandmarkNormalsTensor, {LandmarkNormals::kFeatures, kCells * 4}, head.weights);
            }).find("part of a landmark normal head"),
            std::string::npos);
  // A lone mean-landmarks tensor is a damaged head too, not silently ignored.
  EXPECT_NE(error_of([&](SafeTensorsWriter& w) {
              w.add(kLandmarkNormalsMean, {LandmarkNormals::kLandmarks, 2}, head.mean_landmarks);
            }).find("part of a landmark normal head"),
            std::string::npos);
  // Implausible values: a mean face collapsed to one point, or far outside the crop, and weights
  // far beyond any ridge solution's.
  EXPECT_NE(error_of([&](SafeTensorsWriter& w) {
              LandmarkNormals bad = head;
              std::fill(bad.mean_landmarks.begin(), bad.mean_landmarks.end(), 6.0f);
              add_landmark_normals(w, bad);
            }).find("not a face in a 12-pixel crop"),
            std::string::npos);
  EXPECT_NE(error_of([&](SafeTensorsWriter& w) {
              LandmarkNormals bad = head;
              for (float& v : bad.mean_landmarks) v *= 1e30f;
              add_landmark_normals(w, bad);
            }).find("not a landmark of a 12-pixel crop"),
            std::string::npos);
  EXPECT_NE(error_of([&](SafeTensorsWriter& w) {
              LandmarkNormals bad = head;
              bad.weights[5] = 3e38f;
              add_landmark_normals(w, bad);
            }).find("at element 5, not a finite weight"),
            std::string::npos);
  EXPECT_NE(error_of([&](SafeTensorsWriter& w) {
              add_landmark_normals(w, head);
              w.set_metadata("landmark_normals", "crop 12 grid 5 blend 1 lambda 0");
            }).find("is not 'crop S grid G"),
            std::string::npos);
  EXPECT_NE(error_of([&](SafeTensorsWriter& w) {
              add_landmark_normals(w, head);
              w.set_metadata("landmark_normals", "crop 12 grid 4 blend 1.5 lambda 0");
            }).find("is not 'crop S grid G"),
            std::string::npos);
  EXPECT_NE(error_of([&](SafeTensorsWriter& w) {
              LandmarkNormals bad = head;
              bad.weights[17] = std::nanf("");
              add_landmark_normals(w, bad);
            }).find("at element 17, not a finite weight"),
            std::string::npos);
  EXPECT_NE(error_of([&](SafeTensorsWriter& w) {
              w.set_metadata("landmark_normals", "crop 12 grid 4 blend 1 lambda 0");
              w.add(kLandmarkNormalsTensor, {LandmarkNormals::kFeatures, kCells * 4}, head.weights);
              w.add(kLandmarkNormalsMean, {4, 2}, std::vector<float>(8, 0.0f));
            }).find("lacks the F32 [68, 2] tensor"),
            std::string::npos);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace facetool
