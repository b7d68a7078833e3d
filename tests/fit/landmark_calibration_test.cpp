// Which ICT vertex matches each of dlib's inner landmarks, and what the fit gains from that or from
// other settings: measured on photo-textured synthetic renders whose shape, pose and camera are
// known (docs/fit.md, "Tried on photo-textured renders"). Run by hand:
//   FACETOOL_CALIBRATION_SAMPLES=DIR build/bin/landmark_calibration_test --gtest_also_run_disabled_tests
// DIR: `facetool synth` samples (any size and framing; docs/fit.md gives the command). Optional:
// CALIB_RADIUS (candidate vertices within this many eye distances, 0.12), CALIB_FIRST (first
// landmark calibrated, 17: the jaw keeps its vertices), CALIB_COUNT (samples read),
// CALIB_VARIANTS (only the fit variants whose names contain one of these 6-letter prefixes).
// dlib's points are cached in DIR/dlib-landmarks.txt.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include "core/util/math_constants.h"
#include "libs/face/face_detector.h"
#include "libs/fit/fit_basis.h"
#include "libs/fit/fit_render.h"
#include "libs/fit/landmark_fit.h"
#include "libs/image/crop_framing.h"
#include "libs/io/exr_io.h"
#include "libs/synth/face_parts.h"
#include "libs/synth/pose_camera.h"
#include "synthetic_faces.h"

namespace facetool {
namespace {

struct Render {
  std::string path;
  HeadPose pose;
  Camera camera;
  ShapeWeights weights;
  Landmarks68 dlib{};
  double iod = 0;  // outer eye corners of the truth, pixels
  std::vector<float> projected;  // per candidate vertex: x, y
};

const std::string& metadata(const LayeredImage& image, const std::string& name) {
  const std::string* value = image.find_metadata(name);
  if (!value) throw std::runtime_error(name + " missing");
  return *value;
}

ShapeWeights parse_shape(const FaceModel& model, const std::string& text) {
  ShapeWeights w;
  w.expression.assign(model.expression_names().size(), 0.0f);
  const size_t a = text.find("identity[") + 9, b = text.find(']', a);
  std::istringstream identity(text.substr(a, b - a));
  for (float v; identity >> v;) w.identity.push_back(v);
  const size_t c = text.find("expressions[", b) + 12, d = text.find(']', c);
  std::istringstream expressions(text.substr(c, d - c));
  for (std::string item; expressions >> item;) {
    const size_t eq = item.find('=');
    const auto& names = model.expression_names();
    const auto it = std::find(names.begin(), names.end(), item.substr(0, eq));
    if (it != names.end()) w.expression[it - names.begin()] = std::stof(item.substr(eq + 1));
  }
  return w;
}

TEST(LandmarkCalibration, DISABLED_Measure) {
  const char* dir = std::getenv("FACETOOL_CALIBRATION_SAMPLES");
  if (!dir || !*dir) GTEST_SKIP() << "set FACETOOL_CALIBRATION_SAMPLES to a folder of synth samples";
  const std::string model_dir = testing::fit_face_model_dir();
  ASSERT_FALSE(model_dir.empty());
  auto model = std::make_shared<const FaceModel>(FaceModel::load(model_dir));
  const FitBasis original(model);
  const FaceMesh& neutral = model->neutral();
  const auto& lm = original.landmark_vertices();
  const double neutral_iod = length(neutral.positions[lm[36]] - neutral.positions[lm[45]]);
  const double radius = (std::getenv("CALIB_RADIUS") ? std::atof(std::getenv("CALIB_RADIUS")) : 0.12) * neutral_iod;
  const int first = std::getenv("CALIB_FIRST") ? std::atoi(std::getenv("CALIB_FIRST")) : 17;

  std::vector<uint8_t> is_face(neutral.positions.size(), 0);
  for (size_t t = 0; t < neutral.triangles.size(); ++t)
    if (neutral.triangle_parts[t] == FacePart::kFace)
      for (int32_t v : neutral.triangles[t]) is_face[v] = 1;
  std::vector<std::vector<int>> candidates(68);  // indices into `all`
  std::vector<int32_t> all;
  std::map<int32_t, int> slot;
  auto add = [&](int32_t v) {
    auto [it, fresh] = slot.emplace(v, static_cast<int>(all.size()));
    if (fresh) all.push_back(v);
    return it->second;
  };
  for (int k = 0; k < 68; ++k) {
    candidates[k].push_back(add(lm[k]));
    if (k < first) continue;
    for (size_t v = 0; v < neutral.positions.size(); ++v)
      if (is_face[v] && static_cast<int32_t>(v) != lm[k] &&
          length(neutral.positions[v] - neutral.positions[lm[k]]) < radius)
        candidates[k].push_back(add(static_cast<int32_t>(v)));
  }
  std::printf("%zu candidate vertices (radius %.3f, neutral IOD %.3f)\n", all.size(), radius, neutral_iod);

  std::vector<std::string> paths;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".exr") paths.push_back(e.path().string());
  std::sort(paths.begin(), paths.end());
  if (std::getenv("CALIB_COUNT")) paths.resize(std::min<size_t>(paths.size(), std::atoi(std::getenv("CALIB_COUNT"))));
  // dlib's points per render, cached beside the samples (detection is the slow part).
  const std::string cache_path = std::string(dir) + "/dlib-landmarks.txt";
  std::map<std::string, Landmarks68> cached;
  {
    std::ifstream in(cache_path);
    for (std::string name; in >> name;) {
      Landmarks68 l{};
      for (auto& p : l) in >> p.x >> p.y;
      cached[name] = l;
    }
  }
  std::ofstream cache_out(cache_path, std::ios::app);
  FaceDetector detector;
  std::vector<Render> renders;
  double worst_truth = 0;
  for (const std::string& path : paths) {
    const LayeredImage sample = read_exr(path);
    Render r;
    r.path = path;
    std::istringstream pose(metadata(sample, "facetool:pose_deg"));
    pose >> r.pose.roll_deg >> r.pose.pitch_deg >> r.pose.yaw_deg;
    r.camera.width = sample.width;
    r.camera.height = sample.height;
    r.camera.horizontal_fov_deg = std::stod(metadata(sample, "facetool:fov_deg"));
    r.camera.framing = parse_framing(metadata(sample, "facetool:framing"), path);
    r.weights = parse_shape(*model, metadata(sample, "facetool:shape"));
    FaceMesh mesh = model->build(r.weights);
    apply_pose(mesh, r.pose);
    std::istringstream truth_text(metadata(sample, "facetool:landmarks"));
    Landmarks68 truth{};
    for (auto& p : truth) truth_text >> p.x >> p.y;
    for (int k = 0; k < 68; ++k) {
      const auto q = r.camera.project(mesh.positions[lm[k]]);
      worst_truth = std::max(worst_truth, std::hypot(q[0] - truth[k].x, q[1] - truth[k].y));
    }
    r.iod = std::hypot(truth[36].x - truth[45].x, truth[36].y - truth[45].y);
    RgbImage photo;
    photo.width = sample.width;
    photo.height = sample.height;
    photo.pixels.resize(sample.plane_size() * 3);
    for (int c = 0; c < 3; ++c) {
      const float* plane = sample.plane(sample.require_channel(std::string(1, "RGB"[c]), path));
      for (size_t p = 0; p < sample.plane_size(); ++p) photo.pixels[p * 3 + c] = plane[p];
    }
    const std::string name = std::filesystem::path(path).filename().string();
    if (cached.count(name)) {
      r.dlib = cached[name];
      if (r.dlib[0].x < -1e5) continue;
    } else {
      const auto found = detector.detect(photo);
      Landmarks68 l{};
      for (auto& p : l) p = {-1e6, -1e6};
      if (!found.empty()) l = found[0].landmarks;
      cache_out << name;
      for (const auto& p : l) cache_out << ' ' << p.x << ' ' << p.y;
      cache_out << '\n';
      if (found.empty()) continue;
      r.dlib = l;
    }
    r.projected.resize(all.size() * 2);
    for (size_t i = 0; i < all.size(); ++i) {
      const auto q = r.camera.project(mesh.positions[all[i]]);
      r.projected[2 * i] = static_cast<float>(q[0]);
      r.projected[2 * i + 1] = static_cast<float>(q[1]);
    }
    renders.push_back(std::move(r));
  }
  std::printf("%zu of %zu renders with a face; truth landmarks reproduced within %.4f px\n", renders.size(),
              paths.size(), worst_truth);
  ASSERT_LT(worst_truth, 0.05);

  auto is_train = [](size_t i) { return i % 10 < 7; };
  const double cap = 0.15;
  std::array<int32_t, 68> chosen = lm;
  double old_train = 0, new_train = 0, old_test = 0, new_test = 0;
  int inner = 0;
  for (int k = first; k < 68; ++k) {
    auto cost = [&](int c, bool train) {
      double sum = 0;
      int n = 0;
      for (size_t i = 0; i < renders.size(); ++i) {
        if (is_train(i) != train) continue;
        const Render& r = renders[i];
        const double e = std::hypot(r.projected[2 * c] - r.dlib[k].x, r.projected[2 * c + 1] - r.dlib[k].y) / r.iod;
        sum += std::min(e, cap);
        ++n;
      }
      return sum / std::max(n, 1);
    };
    int best = candidates[k][0];
    double best_cost = cost(best, true);
    for (int c : candidates[k]) {
      const double e = cost(c, true);
      if (e < best_cost) best_cost = e, best = c;
    }
    chosen[k] = all[best];
    const double moved = length(neutral.positions[all[best]] - neutral.positions[lm[k]]) / neutral_iod;
    const double o_tr = cost(candidates[k][0], true), o_te = cost(candidates[k][0], false), n_te = cost(best, false);
    std::printf("landmark %2d: vertex %5d -> %5d (moved %.3f IOD): train %.4f -> %.4f, held out %.4f -> %.4f\n", k,
                lm[k], all[best], moved, o_tr, best_cost, o_te, n_te);
    if (k >= 17) {
      old_train += o_tr, new_train += best_cost, old_test += o_te, new_test += n_te;
      ++inner;
    }
  }
  std::printf("inner points (capped at %.2f IOD): train %.4f -> %.4f, held out %.4f -> %.4f\n", cap,
              old_train / inner, new_train / inner, old_test / inner, new_test / inner);
  std::printf("vertices:");
  for (int k = 0; k < 68; ++k) std::printf("%s%d", k ? ", " : " ", chosen[k]);
  std::printf("\n");

  // Each landmark's spread: RMS of dlib's point minus the truth (vertex_indices.json) over the
  // training renders, in IOD (capped), for inverse-variance weights.
  std::vector<double> sigma(68, 0.0);
  {
    std::vector<int> n(68, 0);
    for (size_t i = 0; i < renders.size(); ++i) {
      if (!is_train(i)) continue;
      const Render& r = renders[i];
      for (int k = 0; k < 68; ++k) {
        const int c = candidates[k][0];
        const double e = std::min(cap, std::hypot(r.projected[2 * c] - r.dlib[k].x, r.projected[2 * c + 1] - r.dlib[k].y) / r.iod);
        sigma[k] += e * e;
        ++n[k];
      }
    }
    for (int k = 0; k < 68; ++k) sigma[k] = std::sqrt(sigma[k] / std::max(n[k], 1));
    std::printf("sigma (IOD):");
    for (int k = 0; k < 68; ++k) std::printf(" %.3f", sigma[k]);
    std::printf("\n");
  }

  // The fit to dlib's points on the held-out renders, for each setting.
  const FitBasis calibrated(model, chosen);
  std::vector<LayeredImage> held;
  std::vector<size_t> held_index;
  for (size_t i = 0; i < renders.size(); ++i)
    if (!is_train(i)) held.push_back(read_exr(renders[i].path)), held_index.push_back(i);
  struct Variant { std::string name; const FitBasis* basis; FitSettings settings; double smoothing = 0; };
  std::vector<Variant> variants;
  variants.push_back({"default", &original, FitSettings{}});
  variants.push_back({"calibrated vertices", &calibrated, FitSettings{}});
  // Inverse-spread weights 1/sigma^p (mean 1 over the inner points): "jaw too" replaces the jaw
  // weight by the jaw points' own 1/sigma^p, "inner" keeps it.
  for (double power : {1.0, 2.0}) {
    FitSettings s;
    s.landmark_weights.resize(68);
    double mean = 0;
    for (int k = 17; k < 68; ++k) mean += std::pow(sigma[k], -power) / 51;
    for (int k = 0; k < 68; ++k) s.landmark_weights[k] = std::pow(sigma[k], -power) / mean / (k < 17 ? s.jaw_weight : 1.0);
    variants.push_back({power == 1 ? "weights 1/sigma (jaw too)" : "weights 1/sigma^2 (jaw too)", &original, s});
    FitSettings t = s;
    for (int k = 0; k < 17; ++k) t.landmark_weights[k] = 1;
    variants.push_back({power == 1 ? "weights 1/sigma (inner)" : "weights 1/sigma^2 (inner)", &original, t});
  }
  for (double id : {1e-2, 5e-2}) {
    FitSettings s;
    s.identity_prior = id;
    variants.push_back({"identity prior " + std::to_string(id), &original, s});
  }
  for (double rs : {0.03, 0.12}) {
    FitSettings s;
    s.robust_scale = rs;
    variants.push_back({"robust scale " + std::to_string(rs), &original, s});
  }
  {
    FitSettings s;
    s.expression_prior = 5e-2;
    variants.push_back({"expression prior 0.05", &original, s});
  }
  for (double smoothing : {0.01, 0.015, 0.02, 0.025, 0.03, 0.04})
    variants.push_back({"smoothed normals " + std::to_string(smoothing), &original, FitSettings{}, smoothing});
  {
    FitSettings s;
    s.jaw = JawHandling::kContour;
    variants.push_back({"contour jaw", &original, s});
    variants.push_back({"contour jaw, smoothed 0.025", &original, s, 0.025});
  }
  const char* only = std::getenv("CALIB_VARIANTS");
  const double bins[4] = {0, 10, 20, 31};
  for (const Variant& variant : variants) {
    if (only && std::string(only).find(variant.name.substr(0, 6)) == std::string::npos) continue;
    double sums[3][3] = {}, signed_error[3] = {};
    double mean_difference[3] = {0, 0, 0};  // fitted minus true normal, summed over the pixels
    int64_t difference_pixels = 0;
    int counts[3] = {};
    for (size_t h = 0; h < held.size(); ++h) {
      const Render& r = renders[held_index[h]];
      const LayeredImage& sample = held[h];
      const double yaw = std::abs(r.pose.yaw_deg);
      const int bin = yaw < bins[1] ? 0 : yaw < bins[2] ? 1 : 2;
      const float* mask = sample.plane(sample.require_channel("mask", r.path));
      const float* normal[3];
      for (int c = 0; c < 3; ++c) normal[c] = sample.plane(sample.require_channel(std::string("normal.") + "XYZ"[c], r.path));
      LandmarkTarget target;
      target.landmarks = r.dlib;
      target.width = r.camera.width;
      target.height = r.camera.height;
      const FaceFit fit = fit_landmarks(*variant.basis, target, variant.settings);
      FitRenderSettings settings;
      settings.visibility = false;
      settings.normal_smoothing = variant.smoothing;
      const FitRendering g = render_fit(*model, fit, nullptr, settings);
      const size_t plane = sample.plane_size();
      double sum = 0;
      int64_t n = 0, inside = 0;
      for (size_t p = 0; p < plane; ++p) {
        if (mask[p] < 0.5f) continue;
        ++inside;
        if (!g.head[p]) continue;
        const double dot = g.normal[p] * normal[0][p] + g.normal[plane + p] * normal[1][p] + g.normal[2 * plane + p] * normal[2][p];
        for (int c = 0; c < 3; ++c) mean_difference[c] += g.normal[c * plane + p] - normal[c][p];
        ++difference_pixels;
        sum += std::acos(std::clamp(dot, -1.0, 1.0)) * 180 / kPi;
        ++n;
      }
      sums[bin][0] += n ? sum / n : 180;
      sums[bin][1] += rotation_difference_deg(fit.pose(), r.pose);
      sums[bin][2] += inside ? static_cast<double>(n) / inside : 0;
      const HeadPose p = fit.pose();
      signed_error[0] += std::abs(p.roll_deg - r.pose.roll_deg);
      signed_error[1] += std::abs(p.pitch_deg - r.pose.pitch_deg);
      signed_error[2] += std::abs(p.yaw_deg - r.pose.yaw_deg);
      ++counts[bin];
    }
    const int total = counts[0] + counts[1] + counts[2];
    std::printf("%-30s", variant.name.c_str());
    double all_normal = 0, all_pose = 0;
    for (int b = 0; b < 3; ++b) {
      std::printf("  %2.0f-%2.0f: %.2f %.2f %.1f%%", bins[b], bins[b + 1], sums[b][0] / std::max(counts[b], 1),
                  sums[b][1] / std::max(counts[b], 1), 100 * sums[b][2] / std::max(counts[b], 1));
      all_normal += sums[b][0], all_pose += sums[b][1];
    }
    std::printf("  all: normal %.2f pose %.2f (|roll| %.2f |pitch| %.2f |yaw| %.2f; %d); mean fitted - true normal "
                "(%.4f, %.4f, %.4f)\n",
                all_normal / total, all_pose / total, signed_error[0] / total, signed_error[1] / total,
                signed_error[2] / total, total, mean_difference[0] / std::max<int64_t>(difference_pixels, 1),
                mean_difference[1] / std::max<int64_t>(difference_pixels, 1),
                mean_difference[2] / std::max<int64_t>(difference_pixels, 1));
    std::fflush(stdout);
  }
}

}  // namespace
}  // namespace facetool
