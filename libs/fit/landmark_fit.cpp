// The landmark fit as a Ceres problem: one analytic-Jacobian residual block per landmark under a
// Cauchy loss, a ridge prior on identity, a smooth-L1 prior on expressions bounded to [0, 1].
#include "libs/fit/landmark_fit.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/util/error.h"
#include "core/util/cpu_time.h"

namespace facetool {

namespace {

constexpr double kPi = 3.14159265358979323846;


// Camera intrinsics and the residual normalisation of one target.
struct Intrinsics {
  FitCamera camera;
  double cx, cy, focal;
};

// One landmark: 2 residuals w * (projection - target) / S over the blocks
// [rotation 3][translation 3 (orthographic: tx, ty, s)][identity K][expression E].
class LandmarkCost final : public ceres::CostFunction {
 public:
  // `row`: [3][stride] (FitBasis::row); the first `expressions` expression modes are fitted.
  LandmarkCost(const double* row, int stride, int identities, int expressions, Point2 target, double weight,
               const Intrinsics& intrinsics)
      : row_(row), stride_(stride), k_(identities), e_(expressions), target_(target), weight_(weight),
        in_(intrinsics) {
    set_num_residuals(2);
    mutable_parameter_block_sizes()->push_back(3);
    mutable_parameter_block_sizes()->push_back(3);
    mutable_parameter_block_sizes()->push_back(k_);
    if (e_ > 0) mutable_parameter_block_sizes()->push_back(e_);
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const double* w = parameters[0];
    const double* t = parameters[1];
    const double* alpha = parameters[2];
    const double* beta = e_ > 0 ? parameters[3] : nullptr;
    const int stride = stride_;
    double p[3];
    for (int c = 0; c < 3; ++c) {
      const double* r = row_ + c * stride;
      double v = r[0];
      for (int k = 0; k < k_; ++k) v += r[1 + k] * alpha[k];
      for (int e = 0; e < e_; ++e) v += r[1 + k_ + e] * beta[e];
      p[c] = v;
    }
    // R p and its derivative by the angle-axis (dual numbers of dimension 3).
    using Jet = ceres::Jet<double, 3>;
    const Jet wj[3] = {Jet(w[0], 0), Jet(w[1], 1), Jet(w[2], 2)};
    const Jet pj[3] = {Jet(p[0]), Jet(p[1]), Jet(p[2])};
    Jet rp[3];
    ceres::AngleAxisRotatePoint(wj, pj, rp);
    // d(pixel)/d(camera point) (2x3) and the projection.
    double du[3] = {0, 0, 0}, dv[3] = {0, 0, 0}, u, v;
    double scale = 1;
    if (in_.camera == FitCamera::kScaledOrthographic) {
      scale = t[2];
      u = in_.cx + t[0] + scale * rp[0].a;
      v = in_.cy - (t[1] + scale * rp[1].a);
      du[0] = scale;
      dv[1] = -scale;
    } else {
      const double qx = rp[0].a + t[0], qy = rp[1].a + t[1], qz = rp[2].a + t[2];
      const double iz = 1.0 / -qz;
      u = in_.cx + in_.focal * qx * iz;
      v = in_.cy - in_.focal * qy * iz;
      du[0] = in_.focal * iz;
      du[2] = in_.focal * qx * iz * iz;
      dv[1] = -in_.focal * iz;
      dv[2] = -in_.focal * qy * iz * iz;
    }
    residuals[0] = weight_ * (u - target_.x);
    residuals[1] = weight_ * (v - target_.y);
    if (!jacobians) return true;
    // For orthographic fits du/dv above include the scale; d(pixel)/d(R p) is what multiplies
    // the rotation's and the modes' derivatives.
    if (jacobians[0]) {
      for (int a = 0; a < 3; ++a) {
        double dqu = 0, dqv = 0;
        for (int c = 0; c < 3; ++c) {
          dqu += du[c] * rp[c].v[a];
          dqv += dv[c] * rp[c].v[a];
        }
        jacobians[0][a] = weight_ * dqu;
        jacobians[0][3 + a] = weight_ * dqv;
      }
    }
    if (jacobians[1]) {
      double* j = jacobians[1];
      if (in_.camera == FitCamera::kScaledOrthographic) {
        j[0] = weight_; j[1] = 0; j[2] = weight_ * rp[0].a;
        j[3] = 0; j[4] = -weight_; j[5] = -weight_ * rp[1].a;
      } else {
        for (int c = 0; c < 3; ++c) {
          j[c] = weight_ * du[c];
          j[3 + c] = weight_ * dv[c];
        }
      }
    }
    if (jacobians[2] || (e_ > 0 && jacobians[3])) {
      double rm[9];
      ceres::AngleAxisToRotationMatrix(w, ceres::RowMajorAdapter3x3(rm));
      // g = d(pixel)/d(p) = d(pixel)/d(Rp) * R (2x3), then each mode's column.
      double gu[3], gv[3];
      for (int c = 0; c < 3; ++c) {
        gu[c] = weight_ * (du[0] * rm[0 + c] + du[1] * rm[3 + c] + du[2] * rm[6 + c]);
        gv[c] = weight_ * (dv[0] * rm[0 + c] + dv[1] * rm[3 + c] + dv[2] * rm[6 + c]);
      }
      const double* rx = row_;
      const double* ry = row_ + stride_;
      const double* rz = row_ + 2 * stride_;
      if (jacobians[2])
        for (int k = 0; k < k_; ++k) {
          const int i = 1 + k;
          jacobians[2][k] = gu[0] * rx[i] + gu[1] * ry[i] + gu[2] * rz[i];
          jacobians[2][k_ + k] = gv[0] * rx[i] + gv[1] * ry[i] + gv[2] * rz[i];
        }
      if (e_ > 0 && jacobians[3])
        for (int e = 0; e < e_; ++e) {
          const int i = 1 + k_ + e;
          jacobians[3][e] = gu[0] * rx[i] + gu[1] * ry[i] + gu[2] * rz[i];
          jacobians[3][e_ + e] = gv[0] * rx[i] + gv[1] * ry[i] + gv[2] * rz[i];
        }
    }
    return true;
  }

 private:
  const double* row_;
  int stride_, k_, e_;
  Point2 target_;
  double weight_;
  Intrinsics in_;
};

// sqrt(lambda) * x_k for every k: the N(0, 1) prior on identity weights.
class RidgePrior final : public ceres::CostFunction {
 public:
  RidgePrior(int size, double lambda) : n_(size), s_(std::sqrt(lambda)) {
    set_num_residuals(size);
    mutable_parameter_block_sizes()->push_back(size);
  }
  bool Evaluate(double const* const* x, double* r, double** j) const override {
    for (int k = 0; k < n_; ++k) r[k] = s_ * x[0][k];
    if (j && j[0]) {
      std::fill(j[0], j[0] + static_cast<size_t>(n_) * n_, 0.0);
      for (int k = 0; k < n_; ++k) j[0][static_cast<size_t>(k) * n_ + k] = s_;
    }
    return true;
  }

 private:
  int n_;
  double s_;
};

// r_k^2 = 2 lambda (sqrt(x_k^2 + eps^2) - eps): quadratic near 0, lambda * 2|x| beyond eps,
// a sparsity prior (smooth L1) on the expression weights.
class SmoothL1Prior final : public ceres::CostFunction {
 public:
  SmoothL1Prior(int size, double lambda, double eps) : n_(size), lambda_(lambda), eps_(eps) {
    set_num_residuals(size);
    mutable_parameter_block_sizes()->push_back(size);
  }
  bool Evaluate(double const* const* x, double* r, double** j) const override {
    if (j && j[0]) std::fill(j[0], j[0] + static_cast<size_t>(n_) * n_, 0.0);
    for (int k = 0; k < n_; ++k) {
      const double b = x[0][k], root = std::sqrt(b * b + eps_ * eps_);
      const double g = 2.0 * lambda_ * (root - eps_);
      r[k] = std::sqrt(std::max(g, 0.0));
      if (j && j[0]) {
        // dr/db = lambda * b / root / r; near 0 its limit sqrt(lambda / eps) * sign(b).
        const double d = r[k] > 1e-12 ? lambda_ * b / root / r[k]
                                      : std::sqrt(lambda_ / eps_) * (b >= 0 ? 1.0 : -1.0);
        j[0][static_cast<size_t>(k) * n_ + k] = d;
      }
    }
    return true;
  }

 private:
  int n_;
  double lambda_, eps_;
};

// Centroid and RMS distance from it of the landmarks.
void spread(const Landmarks68& l, double& mx, double& my, double& s) {
  mx = my = 0;
  for (const Point2& p : l) { mx += p.x; my += p.y; }
  mx /= kLandmarkCount;
  my /= kLandmarkCount;
  double sum = 0;
  for (const Point2& p : l) sum += (p.x - mx) * (p.x - mx) + (p.y - my) * (p.y - my);
  s = std::sqrt(sum / kLandmarkCount);
}

// Vertex position of `row` under weights.
Vec3f row_position(const double* row, int stride, int k, const std::vector<double>& alpha,
                   const std::vector<double>& beta) {
  Vec3f out;
  for (int c = 0; c < 3; ++c) {
    const double* r = row + c * stride;
    double v = r[0];
    for (int i = 0; i < k; ++i) v += r[1 + i] * alpha[i];
    for (size_t e = 0; e < beta.size(); ++e) v += r[1 + k + e] * beta[e];
    out[c] = static_cast<float>(v);
  }
  return out;
}

// The mean face's landmark spread (model units) for the initial scale or distance.
void initialise(const FitBasis& basis, const LandmarkTarget& target, const FitSettings& settings,
                FaceFit& fit) {
  fit.camera = settings.camera;
  fit.width = target.width;
  fit.height = target.height;
  fit.cx = 0.5 * (target.width - 1);
  fit.cy = 0.5 * (target.height - 1);
  fit.focal_px = 0.5 * target.width / std::tan(0.5 * settings.fov_deg * kPi / 180.0);
  double mx, my, s;
  spread(target.landmarks, mx, my, s);
  double ax = 0, ay = 0, az = 0;
  std::array<Vec3f, 68> m;
  for (int i = 0; i < kLandmarkCount; ++i) {
    const double* r = basis.row(basis.landmark_vertices()[i]);
    m[i] = {static_cast<float>(r[0]), static_cast<float>(r[basis.row_stride()]),
            static_cast<float>(r[2 * basis.row_stride()])};
    ax += m[i].x; ay += m[i].y; az += m[i].z;
  }
  ax /= kLandmarkCount; ay /= kLandmarkCount; az /= kLandmarkCount;
  double sm = 0;
  for (const Vec3f& p : m) sm += (p.x - ax) * (p.x - ax) + (p.y - ay) * (p.y - ay);
  sm = std::sqrt(sm / kLandmarkCount);
  if (settings.camera == FitCamera::kScaledOrthographic) {
    fit.scale = s / sm;
    fit.translation[0] = (mx - fit.cx) - fit.scale * ax;
    fit.translation[1] = (fit.cy - my) - fit.scale * ay;
    fit.translation[2] = 0;
  } else {
    const double depth = fit.focal_px * sm / s;  // distance of the landmarks' centroid
    fit.translation[2] = -depth - az;
    fit.translation[0] = (mx - fit.cx) / fit.focal_px * depth - ax;
    fit.translation[1] = (fit.cy - my) / fit.focal_px * depth - ay;
  }
}

// Per jaw landmark, the candidate farthest outwards in the image (the silhouette).
bool choose_contour(const FitBasis& basis, FaceFit& fit) {
  const Mat3f r = fit.rotation_matrix();
  bool changed = false;
  const int stride = basis.row_stride();
  for (int j = 0; j < 17; ++j) {
    const auto& candidates = basis.contour_candidates(j);
    if (candidates.empty()) continue;
    const Vec3f l = row_position(basis.row(basis.landmark_vertices()[j]), stride, basis.identity_count(),
                                 fit.identity, fit.expression);
    // Outwards: the model's +-X axis on the landmark's side, in the image plane.
    const Vec3f out = r * Vec3f{l.x >= 0 ? 1.0f : -1.0f, 0.0f, 0.0f};
    int32_t best = fit.vertices[j];
    double best_value = -1e30;
    for (int32_t v : candidates) {
      const Vec3f q = r * row_position(basis.row(v), stride, basis.identity_count(), fit.identity,
                                       fit.expression);
      const double value = q.x * out.x + q.y * out.y;
      if (value > best_value) {
        best_value = value;
        best = v;
      }
    }
    if (best != fit.vertices[j]) changed = true;
    fit.vertices[j] = best;
  }
  return changed;
}

}  // namespace

const char* fit_camera_name(FitCamera camera) {
  return camera == FitCamera::kScaledOrthographic ? "scaled-orthographic" : "perspective";
}
const char* jaw_handling_name(JawHandling jaw) {
  return jaw == JawHandling::kContour ? "contour" : "down-weighted";
}

Mat3f FaceFit::rotation_matrix() const {
  double rm[9];
  ceres::AngleAxisToRotationMatrix(rotation, ceres::RowMajorAdapter3x3(rm));
  Mat3f m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m.m[i][j] = static_cast<float>(rm[3 * i + j]);
  return m;
}

Vec3f FaceFit::to_camera(Vec3f p) const {
  const Vec3f q = rotation_matrix() * p;
  const Vec3f t{static_cast<float>(translation[0]), static_cast<float>(translation[1]),
                static_cast<float>(translation[2])};
  return camera == FitCamera::kScaledOrthographic ? q * static_cast<float>(scale) + t : q + t;
}

Point2 FaceFit::project(Vec3f q) const {
  if (camera == FitCamera::kScaledOrthographic) return {cx + q.x, cy - q.y};
  return {cx + focal_px * q.x / -q.z, cy - focal_px * q.y / -q.z};
}

Mat3f pose_rotation(const HeadPose& pose) {
  return rotation_y(static_cast<float>(pose.yaw_deg * kPi / 180)) *
         rotation_x(static_cast<float>(pose.pitch_deg * kPi / 180)) *
         rotation_z(static_cast<float>(pose.roll_deg * kPi / 180));
}

HeadPose FaceFit::pose() const {
  const Mat3f r = rotation_matrix();
  HeadPose p;
  p.pitch_deg = std::asin(std::clamp(-static_cast<double>(r.m[1][2]), -1.0, 1.0)) * 180 / kPi;
  p.roll_deg = std::atan2(r.m[1][0], r.m[1][1]) * 180 / kPi;
  p.yaw_deg = std::atan2(r.m[0][2], r.m[2][2]) * 180 / kPi;
  return p;
}

double rotation_difference_deg(const HeadPose& a, const HeadPose& b) {
  const Mat3f d = pose_rotation(a) * pose_rotation(b).transposed();
  const double c = 0.5 * (d.m[0][0] + d.m[1][1] + d.m[2][2] - 1.0);
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180 / kPi;
}

std::vector<FaceFit> fit_landmarks(const FitBasis& basis, const std::vector<LandmarkTarget>& targets,
                                   const FitSettings& settings, SharedFace shared_face) {
  const double start = thread_cpu_seconds();
  check(!targets.empty(), "fit_landmarks: no faces");
  check(settings.landmark_weights.empty() || settings.landmark_weights.size() == static_cast<size_t>(kLandmarkCount),
        "fit_landmarks: landmark_weights has ", settings.landmark_weights.size(), " values; 68 or none");
  const int k = basis.identity_count();
  const int e = settings.fit_expressions ? basis.expression_count() : 0;
  const size_t n = targets.size();
  std::vector<FaceFit> fits(n);
  std::vector<double> shared(k, 0.0);
  const bool shared_identity = shared_face != SharedFace::kNothing, still = shared_face == SharedFace::kHead;
  // A block shared by all targets: its prior counts once per target (see the header).
  const double prior_scale = shared_identity ? static_cast<double>(n) : 1.0;
  for (size_t f = 0; f < n; ++f) {
    check(targets[f].width > 0 && targets[f].height > 0, "fit_landmarks: face ", f, " has no photo size");
    check(!still || (targets[f].width == targets[0].width && targets[f].height == targets[0].height),
          "fit_landmarks: one still head needs photos of one size; face ", f, " is ", targets[f].width, "x",
          targets[f].height, ", face 0 ", targets[0].width, "x", targets[0].height);
    for (const Point2& p : targets[f].landmarks)
      check(std::isfinite(p.x) && std::isfinite(p.y), "fit_landmarks: face ", f, " has a non-finite landmark");
    initialise(basis, targets[f], settings, fits[f]);
    fits[f].identity.assign(k, 0.0);
    fits[f].expression.assign(basis.expression_count(), 0.0);
    fits[f].vertices = basis.landmark_vertices();
  }
  const int rounds = settings.jaw == JawHandling::kContour ? std::max(1, settings.contour_rounds) : 1;
  // Stage -2: camera and pose only (the mean face), a cheap start; stage -1: with identity;
  // then every round fits all (expression weights too). Each starts where the last stopped.
  for (int round = -2; round < rounds; ++round) {
    const bool rigid = round == -2, fixed_expression = round < 0;
    if (!rigid && settings.jaw == JawHandling::kContour) {
      bool changed = round == 0;
      for (FaceFit& fit : fits) changed = choose_contour(basis, fit) || changed;
      if (!changed) break;
    }
    ceres::Problem::Options problem_options;
    problem_options.enable_fast_removal = false;
    ceres::Problem problem(problem_options);
    for (size_t f = 0; f < n; ++f) {
      FaceFit& fit = fits[f];
      // One still head: every target's residuals act on face 0's pose and expression.
      FaceFit& head = still ? fits[0] : fit;
      const bool owner = !still || f == 0;  // adds the priors and bounds of `head`
      double* identity = shared_identity ? shared.data() : fit.identity.data();
      double mx, my, s;
      spread(targets[f].landmarks, mx, my, s);
      const Intrinsics in{fit.camera, fit.cx, fit.cy, fit.focal_px};
      for (int i = 0; i < kLandmarkCount; ++i) {
        const bool jaw = i < 17;
        const double weight =
            (jaw && settings.jaw == JawHandling::kDownWeighted ? settings.jaw_weight : 1.0) *
            (settings.landmark_weights.empty() ? 1.0 : settings.landmark_weights[i]) / s;
        auto* cost = new LandmarkCost(basis.row(fit.vertices[i]), basis.row_stride(), k, e, targets[f].landmarks[i], weight, in);
        std::vector<double*> blocks = {head.rotation, head.translation, identity};
        if (e > 0) blocks.push_back(head.expression.data());
        problem.AddResidualBlock(cost, new ceres::CauchyLoss(settings.robust_scale), blocks);
      }
      if (e > 0 && owner) {
        if (fixed_expression) {
          problem.SetParameterBlockConstant(head.expression.data());
        } else {
          const double weight = settings.expression_prior * (still ? prior_scale : 1.0);
          problem.AddResidualBlock(new SmoothL1Prior(e, weight, settings.expression_smoothness), nullptr,
                                   head.expression.data());
          for (int i = 0; i < e; ++i) {
            problem.SetParameterLowerBound(head.expression.data(), i, 0.0);
            problem.SetParameterUpperBound(head.expression.data(), i, 1.0);
          }
        }
      }
      if (owner && head.camera == FitCamera::kScaledOrthographic)
        problem.SetParameterLowerBound(head.translation, 2, 1e-6);
      if (!shared_identity) {
        if (rigid) problem.SetParameterBlockConstant(identity);
        else problem.AddResidualBlock(new RidgePrior(k, settings.identity_prior), nullptr, identity);
      }
    }
    if (shared_identity) {
      if (rigid) problem.SetParameterBlockConstant(shared.data());
      else problem.AddResidualBlock(new RidgePrior(k, settings.identity_prior * prior_scale), nullptr, shared.data());
    }
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    options.max_num_iterations = settings.max_iterations;
    options.num_threads = 1;
    options.logging_type = ceres::SILENT;
    options.minimizer_progress_to_stdout = false;
    options.function_tolerance = settings.function_tolerance;
    options.parameter_tolerance = 1e-6;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    for (FaceFit& fit : fits) {
      fit.iterations += static_cast<int>(summary.iterations.size());
      if (shared_identity) fit.identity = shared;
      if (still && &fit != &fits[0]) {
        std::copy(fits[0].rotation, fits[0].rotation + 3, fit.rotation);
        std::copy(fits[0].translation, fits[0].translation + 3, fit.translation);
        fit.expression = fits[0].expression;
      }
    }
  }
  const double seconds = (thread_cpu_seconds() - start) / static_cast<double>(n);
  const int stride = basis.row_stride();
  for (size_t f = 0; f < n; ++f) {
    FaceFit& fit = fits[f];
    fit.seconds = seconds;
    double sum = 0;
    for (int i = 0; i < kLandmarkCount; ++i) {
      const Point2 p = fit.project(fit.to_camera(row_position(basis.row(fit.vertices[i]), stride, k, fit.identity, fit.expression)));
      sum += (p.x - targets[f].landmarks[i].x) * (p.x - targets[f].landmarks[i].x) +
             (p.y - targets[f].landmarks[i].y) * (p.y - targets[f].landmarks[i].y);
    }
    fit.rms_px = std::sqrt(sum / kLandmarkCount);
  }
  return fits;
}

FaceFit fit_landmarks(const FitBasis& basis, const LandmarkTarget& target, const FitSettings& settings) {
  return fit_landmarks(basis, std::vector<LandmarkTarget>{target}, settings, SharedFace::kNothing)[0];
}

}  // namespace facetool
