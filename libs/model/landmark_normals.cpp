// The landmark normal head: features, prediction, blending, the ridge fit and its place in a weights file.
#include "libs/model/landmark_normals.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "core/util/error.h"
#include "libs/image/similarity_transform.h"

namespace facetool {
namespace {

// The similarity that best maps a face's inner points (17-67) onto `mean` (least squares).
Similarity2 similarity_onto(const float* xy, const std::vector<float>& mean) {
  std::vector<Point2> from, to;
  for (int i = 17; i < LandmarkNormals::kLandmarks; ++i) {
    from.push_back({xy[2 * i], xy[2 * i + 1]});
    to.push_back({mean[2 * i], mean[2 * i + 1]});
  }
  return fit_similarity(from, to);
}

// The features of a face moved onto the mean by `t`.
std::vector<double> aligned_features(const float* xy, const Similarity2& t, int crop_size) {
  std::vector<float> aligned(2 * LandmarkNormals::kLandmarks);
  for (int i = 0; i < LandmarkNormals::kLandmarks; ++i) {
    const Point2 q = t.apply({xy[2 * i], xy[2 * i + 1]});
    aligned[2 * i] = static_cast<float>(q.x);
    aligned[2 * i + 1] = static_cast<float>(q.y);
  }
  return LandmarkNormals::features(aligned.data(), crop_size);
}

// Turns a normal (x right, y up) by the similarity's rotation (image axes, y down); `sign` -1
// turns it back.
void rotate_normal(const Similarity2& t, double sign, double& nx, double& ny) {
  const double scale = std::hypot(t.a, t.b), c = t.a / scale, s = sign * t.b / scale;
  const double ix = nx, iy = -ny;
  const double rx = c * ix - s * iy, ry = s * ix + c * iy;
  nx = rx;
  ny = -ry;
}

// Solves A x = b for the symmetric positive definite A [n][n] (Cholesky), for `m` right-hand
// sides b [n][m] at once; b is overwritten with x.
void cholesky_solve(std::vector<double> a, int n, std::vector<double>& b, int m) {
  for (int j = 0; j < n; ++j) {
    double d = a[j * n + j];
    for (int k = 0; k < j; ++k) d -= a[j * n + k] * a[j * n + k];
    check(d > 0, "landmark normals: the normal equations are singular (too few faces, or lambda 0)");
    const double l = std::sqrt(d);
    a[j * n + j] = l;
    for (int i = j + 1; i < n; ++i) {
      double v = a[i * n + j];
      for (int k = 0; k < j; ++k) v -= a[i * n + k] * a[j * n + k];
      a[i * n + j] = v / l;
    }
  }
  for (int i = 0; i < n; ++i) {  // L y = b
    for (int k = 0; k < i; ++k)
      for (int c = 0; c < m; ++c) b[i * m + c] -= a[i * n + k] * b[k * m + c];
    for (int c = 0; c < m; ++c) b[i * m + c] /= a[i * n + i];
  }
  for (int i = n - 1; i >= 0; --i) {  // L^T x = y
    for (int k = i + 1; k < n; ++k)
      for (int c = 0; c < m; ++c) b[i * m + c] -= a[k * n + i] * b[k * m + c];
    for (int c = 0; c < m; ++c) b[i * m + c] /= a[i * n + i];
  }
}

}  // namespace

std::vector<double> LandmarkNormals::features(const float* xy, int crop_size) {
  std::vector<double> f(kFeatures);
  const double half = 0.5 * crop_size;
  for (int k = 0; k < 2 * kLandmarks; ++k) {
    const double c = (xy[k] - half) / half;
    f[k] = c;
    f[2 * kLandmarks + k] = c * c;
  }
  f[kFeatures - 1] = 1.0;
  return f;
}

void LandmarkNormals::predict(const float* xy, std::vector<float>& normal, std::vector<float>& mask) const {
  check(grid >= 1 && crop_size >= grid && weights.size() == static_cast<size_t>(kFeatures) * grid * grid * kValues &&
            mean_landmarks.size() == 2 * kLandmarks,
        "landmark normals: a head of ", weights.size(), " weights and ", mean_landmarks.size(),
        " mean coordinates does not fit its grid of ", grid);
  const Similarity2 t = similarity_onto(xy, mean_landmarks);
  const std::vector<double> f = aligned_features(xy, t, crop_size);
  const size_t cells = static_cast<size_t>(grid) * grid * kValues;
  std::vector<double> coarse(cells, 0.0);
  for (int k = 0; k < kFeatures; ++k) {
    const float* w = weights.data() + k * cells;
    for (size_t c = 0; c < cells; ++c) coarse[c] += f[k] * w[c];
  }
  // Each crop pixel read from the map at its place in the mean's frame (bilinear between the
  // cells' centres), its normal turned back by the similarity's rotation.
  const int s = crop_size;
  const size_t plane = static_cast<size_t>(s) * s;
  normal.assign(3 * plane, 0.0f);
  mask.assign(plane, 0.0f);
  const double to_grid = static_cast<double>(grid) / s;
  for (int y = 0; y < s; ++y)
    for (int x = 0; x < s; ++x) {
      const Point2 q = t.apply({static_cast<double>(x), static_cast<double>(y)});
      const double gx = (q.x + 0.5) * to_grid - 0.5, gy = (q.y + 0.5) * to_grid - 0.5;
      const int x0 = std::clamp(static_cast<int>(std::floor(gx)), 0, std::max(0, grid - 2));
      const int y0 = std::clamp(static_cast<int>(std::floor(gy)), 0, std::max(0, grid - 2));
      const int x1 = std::min(x0 + 1, grid - 1), y1 = std::min(y0 + 1, grid - 1);
      const double fx = std::clamp(gx - x0, 0.0, 1.0), fy = std::clamp(gy - y0, 0.0, 1.0);
      double v[kValues];
      for (int c = 0; c < kValues; ++c) {
        auto at = [&](int cy0, int cx0) { return coarse[(static_cast<size_t>(cy0) * grid + cx0) * kValues + c]; };
        v[c] = (1 - fy) * ((1 - fx) * at(y0, x0) + fx * at(y0, x1)) + fy * ((1 - fx) * at(y1, x0) + fx * at(y1, x1));
      }
      const size_t p = static_cast<size_t>(y) * s + x;
      mask[p] = static_cast<float>(std::clamp(v[3], 0.0, 1.0));
      const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      if (mask[p] <= 0.0f || length < 1e-9) continue;
      double nx = v[0] / length, ny = v[1] / length;
      rotate_normal(t, -1.0, nx, ny);
      normal[p] = static_cast<float>(nx);
      normal[plane + p] = static_cast<float>(ny);
      normal[2 * plane + p] = static_cast<float>(v[2] / length);
    }
}

void LandmarkNormals::blend_into(const float* xy, float* normal, std::vector<float>* mask_out) const {
  std::vector<float> head, own_mask;
  std::vector<float>& mask = mask_out ? *mask_out : own_mask;
  predict(xy, head, mask);
  const size_t plane = mask.size();
  for (size_t p = 0; p < plane; ++p) {
    const double w = blend * std::clamp((mask[p] - 0.3) / 0.4, 0.0, 1.0);
    if (w <= 0) continue;
    double n[3], length = 0;
    for (int c = 0; c < 3; ++c) {
      n[c] = w * head[c * plane + p] + (1 - w) * normal[c * plane + p];
      length += n[c] * n[c];
    }
    length = std::sqrt(length);
    if (length < 1e-9) continue;  // opposite normals at w = 0.5: keep the network's
    for (int c = 0; c < 3; ++c) normal[c * plane + p] = static_cast<float>(n[c] / length);
  }
}

LandmarkNormalsFit::LandmarkNormalsFit(int crop_size, int grid, std::vector<float> mean_landmarks)
    : crop_size_(crop_size), grid_(grid), mean_(std::move(mean_landmarks)) {
  check(grid >= 1 && crop_size >= grid && crop_size % grid == 0, "landmark normals: the crop size ", crop_size,
        " is not a multiple of the grid ", grid);
  check(mean_.size() == 2 * LandmarkNormals::kLandmarks, "landmark normals: the mean landmarks need 136 coordinates");
  constexpr int n = LandmarkNormals::kFeatures;
  gram_.assign(static_cast<size_t>(n) * n, 0.0);
  moment_.assign(static_cast<size_t>(n) * grid * grid * LandmarkNormals::kValues, 0.0);
}

void LandmarkNormalsFit::add(const float* xy, const float* normal, const float* mask) {
  constexpr int n = LandmarkNormals::kFeatures, kv = LandmarkNormals::kValues;
  const Similarity2 t = similarity_onto(xy, mean_);
  const std::vector<double> f = aligned_features(xy, t, crop_size_);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) gram_[i * n + j] += f[i] * f[j];
  // The labels in the mean's frame (each pixel q there read at p = t^-1(q) in the crop, nearest
  // pixel; the normal turned by the similarity), averaged over each cell: the mask as 0 or 1,
  // the normal where it is 1.
  const Similarity2 inverse = t.inverse();
  const int cell = crop_size_ / grid_;
  const size_t plane = static_cast<size_t>(crop_size_) * crop_size_;
  const size_t cells = static_cast<size_t>(grid_) * grid_ * kv;
  std::vector<double> y(cells, 0.0);
  for (int qy = 0; qy < crop_size_; ++qy)
    for (int qx = 0; qx < crop_size_; ++qx) {
      const Point2 from = inverse.apply({static_cast<double>(qx), static_cast<double>(qy)});
      const long px = std::lround(from.x), py = std::lround(from.y);
      if (px < 0 || py < 0 || px >= crop_size_ || py >= crop_size_) continue;
      const size_t p = static_cast<size_t>(py) * crop_size_ + static_cast<size_t>(px);
      if (!(mask[p] > 0.5f)) continue;
      double nx = normal[p], ny = normal[plane + p];
      rotate_normal(t, 1.0, nx, ny);
      double* target = y.data() + (static_cast<size_t>(qy / cell) * grid_ + qx / cell) * kv;
      target[0] += nx;
      target[1] += ny;
      target[2] += normal[2 * plane + p];
      target[3] += 1.0;
    }
  const double area = 1.0 / (cell * cell);
  for (int i = 0; i < n; ++i) {
    double* m = moment_.data() + i * cells;
    const double fi = f[i] * area;
    for (size_t c = 0; c < cells; ++c) m[c] += fi * y[c];
  }
  ++count_;
}

std::vector<float> mean_landmarks(const std::vector<float>& landmarks) {
  constexpr size_t kPoints = 2 * LandmarkNormals::kLandmarks;
  check(!landmarks.empty() && landmarks.size() % kPoints == 0, "landmark normals: ", landmarks.size(),
        " coordinates are not whole faces of 68 points");
  std::vector<double> sum(kPoints, 0.0);
  for (size_t k = 0; k < landmarks.size(); ++k) sum[k % kPoints] += landmarks[k];
  std::vector<float> mean(kPoints);
  const double faces = static_cast<double>(landmarks.size() / kPoints);
  for (size_t k = 0; k < kPoints; ++k) mean[k] = static_cast<float>(sum[k] / faces);
  return mean;
}

LandmarkNormals LandmarkNormalsFit::solve(double lambda, float blend) const {
  check(count_ > 0, "landmark normals: no faces to fit");
  check(lambda >= 0 && std::isfinite(lambda), "landmark normals: lambda must be finite and not negative (", lambda, ")");
  check(blend >= 0.0f && blend <= 1.0f, "landmark normals: the blend must lie in [0, 1] (", blend, ")");
  constexpr int n = LandmarkNormals::kFeatures;
  std::vector<double> a = gram_;
  for (int i = 0; i < n; ++i) a[i * n + i] += lambda;
  std::vector<double> w = moment_;
  const int cells = grid_ * grid_ * LandmarkNormals::kValues;
  cholesky_solve(std::move(a), n, w, cells);
  LandmarkNormals head;
  head.crop_size = crop_size_;
  head.grid = grid_;
  head.blend = blend;
  head.lambda = lambda;
  head.weights.assign(w.begin(), w.end());
  head.mean_landmarks = mean_;
  return head;
}

namespace {
constexpr float kMaxHeadWeight = 1e4f;
}  // namespace

std::shared_ptr<const LandmarkNormals> read_landmark_normals(const SafeTensors& file, const std::string& path) {
  const auto it = file.metadata().find("landmark_normals");
  const bool tensor = file.contains(kLandmarkNormalsTensor), mean = file.contains(kLandmarkNormalsMean);
  if (it == file.metadata().end() && !tensor && !mean) return nullptr;
  check(it != file.metadata().end() && tensor && mean, "weights file '", path, "' holds part of a landmark normal head ",
        "(the tensors '", kLandmarkNormalsTensor, "' and '", kLandmarkNormalsMean,
        "' and the metadata 'landmark_normals' go together): a damaged file");
  auto head = std::make_shared<LandmarkNormals>();
  std::istringstream in(it->second);
  std::string key;
  bool ok = true;
  while (ok && in >> key) {
    if (key == "crop") ok = static_cast<bool>(in >> head->crop_size);
    else if (key == "grid") ok = static_cast<bool>(in >> head->grid);
    else if (key == "blend") ok = static_cast<bool>(in >> head->blend);
    else if (key == "lambda") ok = static_cast<bool>(in >> head->lambda);
    else ok = false;
  }
  check(ok && head->grid >= 1 && head->crop_size >= head->grid && head->crop_size % head->grid == 0 &&
            head->blend >= 0.0f && head->blend <= 1.0f,
        "weights file '", path, "': metadata landmark_normals '", it->second,
        "' is not 'crop S grid G blend B lambda L' with S a multiple of G and B in [0, 1]");
  const SafeTensors::Entry& e = file.entry(kLandmarkNormalsTensor);
  const std::vector<int64_t> shape{LandmarkNormals::kFeatures,
                                   static_cast<int64_t>(head->grid) * head->grid * LandmarkNormals::kValues};
  check(e.dtype == "F32" && e.shape == shape, "weights file '", path, "': tensor '", kLandmarkNormalsTensor,
        "' is not F32 [", shape[0], ", ", shape[1], "]");
  head->weights = file.floats(kLandmarkNormalsTensor);
  check(file.contains(kLandmarkNormalsMean) && file.entry(kLandmarkNormalsMean).dtype == "F32" &&
            file.entry(kLandmarkNormalsMean).shape == std::vector<int64_t>{LandmarkNormals::kLandmarks, 2},
        "weights file '", path, "': its landmark normal head lacks the F32 [68, 2] tensor '", kLandmarkNormalsMean, "'");
  head->mean_landmarks = file.floats(kLandmarkNormalsMean);
  // Plausible values, not only finite ones: the mean face lies in the crop and is spread over it
  // (at least an eighth of the crop each way); the ridge weights stay far below kMaxHeadWeight
  // (the shipped head's largest is 49).
  float lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (size_t k = 0; k < head->mean_landmarks.size(); ++k) {
    const float v = head->mean_landmarks[k];
    check(std::isfinite(v) && v >= -head->crop_size && v <= 2.0f * head->crop_size, "weights file '", path,
          "': tensor '", kLandmarkNormalsMean, "' holds ", v, ", not a landmark of a ", head->crop_size,
          "-pixel crop (a damaged file)");
    lo[k % 2] = std::min(lo[k % 2], v);
    hi[k % 2] = std::max(hi[k % 2], v);
  }
  check(hi[0] - lo[0] >= head->crop_size / 8.0f && hi[1] - lo[1] >= head->crop_size / 8.0f, "weights file '", path,
        "': tensor '", kLandmarkNormalsMean, "' spans ", hi[0] - lo[0], " x ", hi[1] - lo[1],
        " pixels, not a face in a ", head->crop_size, "-pixel crop (a damaged file)");
  for (size_t k = 0; k < head->weights.size(); ++k)
    check(std::isfinite(head->weights[k]) && std::abs(head->weights[k]) <= kMaxHeadWeight, "weights file '", path,
          "': tensor '", kLandmarkNormalsTensor, "' holds ", head->weights[k], " at element ", k,
          ", not a finite weight within +-", kMaxHeadWeight, " (a damaged file)");
  return head;
}

void add_landmark_normals(SafeTensorsWriter& writer, const LandmarkNormals& head) {
  std::ostringstream meta;
  meta.precision(9);
  meta << "crop " << head.crop_size << " grid " << head.grid << " blend " << head.blend << " lambda " << head.lambda;
  writer.set_metadata("landmark_normals", meta.str());
  writer.add(kLandmarkNormalsTensor,
             {LandmarkNormals::kFeatures, static_cast<int64_t>(head.grid) * head.grid * LandmarkNormals::kValues},
             head.weights);
  writer.add(kLandmarkNormalsMean, {LandmarkNormals::kLandmarks, 2}, head.mean_landmarks);
}

bool is_landmark_normals_tensor(const std::string& name) {
  return name == kLandmarkNormalsTensor || name == kLandmarkNormalsMean;
}

}  // namespace facetool
