// Procedural albedo: anchored skin-tone ramp, smooth value noise, landmark-shaped lips and brows.
#include "libs/synth/albedo.h"
#include "core/util/math_constants.h"

#include <algorithm>
#include <cmath>

namespace facetool {
namespace {

// Matches the cornea cut in face_model.cpp: the iris fills the opening of the outer shell.
constexpr float kIrisHalfAngleDeg = 30.0f;

float smoothstep(float edge0, float edge1, float x) {
  const float t = std::clamp((x - edge0) / (edge1 - edge0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

Vec3f mix(Vec3f a, Vec3f b, float t) { return a * (1.0f - t) + b * t; }
Vec3f multiply(Vec3f a, Vec3f b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
Vec3f clamp01(Vec3f a) {
  return {std::clamp(a.x, 0.0f, 1.0f), std::clamp(a.y, 0.0f, 1.0f), std::clamp(a.z, 0.0f, 1.0f)};
}

// Interpolates in log space between anchors spread evenly over t in [0, 1].
Vec3f log_ramp(const std::vector<Vec3f>& anchors, double t) {
  const double scaled = std::clamp(t, 0.0, 1.0) * (anchors.size() - 1);
  const size_t k = std::min(static_cast<size_t>(scaled), anchors.size() - 2);
  const float f = static_cast<float>(scaled - k);
  Vec3f out;
  for (int c = 0; c < 3; ++c)
    out[c] = std::exp(std::log(anchors[k][c]) * (1 - f) + std::log(anchors[k + 1][c]) * f);
  return out;
}

// Smooth 3D value noise in [-1, 1] from an integer-lattice hash (trilinear, smoothstep-eased).
float lattice_value(int x, int y, int z) {
  uint64_t h = static_cast<uint64_t>(x) * 0x8DA6B343u ^ static_cast<uint64_t>(y) * 0xD8163841u ^
               static_cast<uint64_t>(z) * 0xCB1AB31Fu;
  h = (h ^ (h >> 29)) * 0xBF58476D1CE4E5B9ull;
  h ^= h >> 32;
  return static_cast<float>(h & 0xFFFFFF) / 8388607.5f - 1.0f;
}

float value_noise(Vec3f p) {
  const int x0 = static_cast<int>(std::floor(p.x)), y0 = static_cast<int>(std::floor(p.y)),
            z0 = static_cast<int>(std::floor(p.z));
  const float fx = smoothstep(0, 1, p.x - x0), fy = smoothstep(0, 1, p.y - y0),
              fz = smoothstep(0, 1, p.z - z0);
  float result = 0.0f;
  for (int dz = 0; dz <= 1; ++dz)
    for (int dy = 0; dy <= 1; ++dy)
      for (int dx = 0; dx <= 1; ++dx) {
        const float w = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy) * (dz ? fz : 1 - fz);
        result += w * lattice_value(x0 + dx, y0 + dy, z0 + dz);
      }
  return result;
}

// Signed distance from q to a closed polygon (negative inside), in the polygon's plane.
float polygon_signed_distance(const std::vector<std::array<float, 2>>& polygon, float qx, float qy) {
  float best = 1e30f;
  bool inside = false;
  for (size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const float ax = polygon[j][0], ay = polygon[j][1], bx = polygon[i][0], by = polygon[i][1];
    const float ex = bx - ax, ey = by - ay;
    const float t = std::clamp(((qx - ax) * ex + (qy - ay) * ey) / (ex * ex + ey * ey + 1e-12f), 0.0f, 1.0f);
    const float dx = qx - (ax + t * ex), dy = qy - (ay + t * ey);
    best = std::min(best, std::sqrt(dx * dx + dy * dy));
    if ((ay > qy) != (by > qy) && qx < ax + (qy - ay) * ex / (ey + 1e-12f)) inside = !inside;
  }
  return inside ? -best : best;
}

// Distance from q to a polyline and the position along it in [0, 1].
void polyline_distance(const std::vector<std::array<float, 2>>& line, float qx, float qy,
                       float& distance, float& along) {
  distance = 1e30f;
  along = 0.0f;
  for (size_t i = 0; i + 1 < line.size(); ++i) {
    const float ax = line[i][0], ay = line[i][1], ex = line[i + 1][0] - ax, ey = line[i + 1][1] - ay;
    const float t = std::clamp(((qx - ax) * ex + (qy - ay) * ey) / (ex * ex + ey * ey + 1e-12f), 0.0f, 1.0f);
    const float dx = qx - (ax + t * ex), dy = qy - (ay + t * ey);
    const float d = std::sqrt(dx * dx + dy * dy);
    if (d < distance) {
      distance = d;
      along = (static_cast<float>(i) + t) / static_cast<float>(line.size() - 1);
    }
  }
}

}  // namespace

AlbedoParams sample_albedo(Random& random) {
  AlbedoParams a;
  a.melanin = random.uniform();
  // Linear-RGB anchors from very light to very dark skin (reflectance-like values).
  static const std::vector<Vec3f> skin_anchors = {
      {0.78f, 0.58f, 0.49f}, {0.62f, 0.42f, 0.32f}, {0.44f, 0.27f, 0.17f},
      {0.24f, 0.13f, 0.08f}, {0.09f, 0.05f, 0.035f}};
  a.skin = log_ramp(skin_anchors, a.melanin);
  a.skin = clamp01(multiply(a.skin, {static_cast<float>(random.uniform(0.94, 1.06)), 1.0f,
                                     static_cast<float>(random.uniform(0.88, 1.12))}));
  a.lips = clamp01(multiply(a.skin, Vec3f{0.88f, 0.58f, 0.62f} *
                                        static_cast<float>(random.uniform(0.8, 1.05))));
  // Hair from blond to black, darker on average for darker skin.
  static const std::vector<Vec3f> hair_anchors = {
      {0.42f, 0.30f, 0.15f}, {0.16f, 0.09f, 0.045f}, {0.05f, 0.03f, 0.02f}, {0.015f, 0.012f, 0.01f}};
  a.hair = log_ramp(hair_anchors, std::max(random.uniform(), a.melanin * 0.8));
  a.brow_density = static_cast<float>(random.uniform(0.55, 0.95));
  static const std::vector<Vec3f> iris_palette = {
      {0.10f, 0.05f, 0.02f}, {0.04f, 0.025f, 0.015f}, {0.18f, 0.13f, 0.05f},
      {0.10f, 0.15f, 0.07f}, {0.10f, 0.16f, 0.28f}, {0.18f, 0.20f, 0.22f}};
  a.iris = iris_palette[random.index(iris_palette.size())] *
           static_cast<float>(random.uniform(0.8, 1.2));
  a.sclera = Vec3f{0.72f, 0.67f, 0.61f} * static_cast<float>(random.uniform(0.8, 1.0));
  a.variation = static_cast<float>(random.uniform(0.04, 0.12));
  a.redness = static_cast<float>(random.uniform(0.0, 0.12));
  a.noise_offset = {static_cast<float>(random.uniform(0, 1000)),
                    static_cast<float>(random.uniform(0, 1000)),
                    static_cast<float>(random.uniform(0, 1000))};
  return a;
}

AlbedoModel::AlbedoModel(const FaceMesh& reference, const std::vector<int32_t>& landmarks) {
  const auto& r = reference.reference_positions;
  // Scale: the fitted region's size when there are no landmarks.
  Vec3f low{1e30f, 1e30f, 1e30f}, high{-1e30f, -1e30f, -1e30f};
  for (const Vec3f& p : r)
    for (int k = 0; k < 3; ++k) {
      low[k] = std::min(low[k], p[k]);
      high[k] = std::max(high[k], p[k]);
    }
  scale_ = std::max(0.4f * (high.x - low.x), 1e-6f);
  auto valid = [&](int index) {
    return index < static_cast<int>(landmarks.size()) && landmarks[index] >= 0 &&
           landmarks[index] < static_cast<int32_t>(r.size());
  };
  bool all_valid = landmarks.size() >= 68;
  for (int k = 0; k < 68 && all_valid; ++k) all_valid = valid(k);
  if (all_valid) {
    auto at = [&](int k) { return r[landmarks[k]]; };
    has_features_ = true;
    scale_ = length(at(36) - at(45));
    lip_front_z_ = 1e30f;
    for (int k = 48; k <= 59; ++k) {
      outer_lip_.push_back({at(k).x, at(k).y});
      lip_front_z_ = std::min(lip_front_z_, at(k).z);
    }
    lip_front_z_ -= 0.3f * scale_;
    brow_front_z_ = 1e30f;
    for (int b = 0; b < 2; ++b)
      for (int k = 17 + 5 * b; k <= 21 + 5 * b; ++k) {
        brows_[b].push_back({at(k).x, at(k).y});
        brow_front_z_ = std::min(brow_front_z_, at(k).z);
      }
    brow_front_z_ -= 0.3f * scale_;
    // Cheek centres: below the eye centres, halfway to the mouth corners.
    const Vec3f eye_r = (at(36) + at(39)) * 0.5f, eye_l = (at(42) + at(45)) * 0.5f;
    cheeks_[0] = (eye_r + at(48)) * 0.5f + Vec3f{-0.1f * scale_, 0, 0};
    cheeks_[1] = (eye_l + at(54)) * 0.5f + Vec3f{0.1f * scale_, 0, 0};
    nose_tip_ = at(30);
  }
  // Eyes: the fitted centre of each inner eyeball shell (kIris); the iris is the cap within
  // the cornea's half-angle of +Z (the neutral gaze), the pupil the middle of it.
  std::array<std::vector<Vec3f>, 2> shell;
  for (size_t t = 0; t < reference.triangles.size(); ++t) {
    if (reference.triangle_parts[t] != FacePart::kIris) continue;
    for (int32_t v : reference.triangles[t]) shell[r[v].x >= 0 ? 0 : 1].push_back(r[v]);
  }
  has_eyes_ = shell[0].size() >= 4 && shell[1].size() >= 4;
  if (has_eyes_)
    for (int side = 0; side < 2; ++side) eye_centre_[side] = fit_sphere_centre(shell[side]);
}

Vec3f AlbedoModel::skin(const AlbedoParams& params, Vec3f p) const {
  const Vec3f q = p * (1.0f / scale_);
  // Two octaves of smooth noise: blotchy luminance, plus a slight independent hue drift.
  const float lum = value_noise(q * 1.5f + params.noise_offset) +
                    0.5f * value_noise(q * 3.0f + params.noise_offset * 1.7f);
  const float hue = value_noise(q * 1.2f + params.noise_offset * 0.6f + Vec3f{17, 3, 5});
  Vec3f color = params.skin * (1.0f + params.variation * lum / 1.5f);
  color = multiply(color, {1.0f + 0.03f * hue, 1.0f, 1.0f - 0.03f * hue});
  if (has_features_) {
    float blush = 0.0f;
    for (const Vec3f& c : cheeks_) {
      const float d = length(p - c) / (0.35f * scale_);
      blush += std::exp(-d * d);
    }
    const float dn = length(p - nose_tip_) / (0.25f * scale_);
    blush += 0.6f * std::exp(-dn * dn);
    color = multiply(color, {1.0f + params.redness * blush * 0.5f, 1.0f - params.redness * blush,
                             1.0f - params.redness * blush});
  }
  return clamp01(color);
}

float AlbedoModel::lip_weight(Vec3f p) const {
  if (!has_features_ || p.z < lip_front_z_) return 0.0f;
  const float sd = polygon_signed_distance(outer_lip_, p.x, p.y);
  const float edge = 0.025f * scale_;
  return 1.0f - smoothstep(-edge, edge, sd);
}

float AlbedoModel::brow_weight(Vec3f p) const {
  if (!has_features_ || p.z < brow_front_z_) return 0.0f;
  float weight = 0.0f;
  for (const auto& brow : brows_) {
    // The band sits just below the landmark line; thick at the inner end, thin at the outer.
    float distance, along;
    polyline_distance(brow, p.x, p.y + 0.035f * scale_, distance, along);
    const bool inner_is_last = std::fabs(brow.back()[0]) < std::fabs(brow.front()[0]);
    const float inner = inner_is_last ? along : 1.0f - along;
    const float half_width = scale_ * (0.035f + 0.03f * inner);
    weight = std::max(weight, 1.0f - smoothstep(0.6f * half_width, half_width, distance));
  }
  return weight;
}

Vec3f AlbedoModel::evaluate_skin(const AlbedoParams& params, Vec3f p) const { return clamp01(skin(params, p)); }

Vec3f AlbedoModel::evaluate(const AlbedoParams& params, FacePart part, Vec3f p) const {
  switch (part) {
    case FacePart::kSclera: {
      const float n = value_noise(p * (8.0f / scale_) + params.noise_offset);
      return clamp01(params.sclera * (1.0f + 0.04f * n));
    }
    case FacePart::kIris: {
      if (!has_eyes_) return clamp01(params.iris);
      const Vec3f d = normalized(p - eye_centre_[p.x >= 0 ? 0 : 1]);
      const float angle = std::acos(std::clamp(d.z, -1.0f, 1.0f)) * (180.0f / static_cast<float>(kPi));
      const float t = angle / kIrisHalfAngleDeg;  // 0 at the pupil centre, 1 at the limbus
      const Vec3f pupil{0.01f, 0.01f, 0.01f};
      const Vec3f ring = params.iris * (0.75f + 0.5f * t);  // lighter towards the limbus
      Vec3f color = mix(pupil, ring, smoothstep(0.34f, 0.42f, t));
      color = mix(color, params.sclera, smoothstep(0.95f, 1.05f, t));
      return clamp01(color);
    }
    case FacePart::kEyeSocket:
      return clamp01(multiply(skin(params, p), {0.9f, 0.68f, 0.68f}));
    default:
      break;
  }
  Vec3f color = skin(params, p);
  color = mix(color, params.lips, lip_weight(p));
  color = mix(color, params.hair, params.brow_density * brow_weight(p));
  return clamp01(color);
}

}  // namespace facetool
