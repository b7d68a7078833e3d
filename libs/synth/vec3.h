// Vec3f: the small float 3-vector the generator's geometry code uses.
#pragma once

#include <cmath>

namespace facetool {

struct Vec3f {
  float x = 0, y = 0, z = 0;
  float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

inline Vec3f operator+(Vec3f a, Vec3f b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3f operator-(Vec3f a, Vec3f b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3f operator*(Vec3f a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3f operator*(float s, Vec3f a) { return a * s; }
inline Vec3f& operator+=(Vec3f& a, Vec3f b) { return a = a + b; }
inline float dot(Vec3f a, Vec3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3f cross(Vec3f a, Vec3f b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vec3f a) { return std::sqrt(dot(a, a)); }
// a / |a|, or (0, 0, 0) for a zero vector.
inline Vec3f normalized(Vec3f a) {
  const float l = length(a);
  return l > 0 ? a * (1.0f / l) : Vec3f{};
}

// A row-major 3x3 matrix acting on column vectors.
struct Mat3f {
  float m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Vec3f operator*(Vec3f v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  Mat3f operator*(const Mat3f& b) const {
    Mat3f r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        r.m[i][j] = m[i][0] * b.m[0][j] + m[i][1] * b.m[1][j] + m[i][2] * b.m[2][j];
    return r;
  }
  Mat3f transposed() const {
    Mat3f r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r.m[i][j] = m[j][i];
    return r;
  }
};

// Counter-clockwise (right-handed) rotations by `radians` about the X, Y and Z axes.
inline Mat3f rotation_x(float radians) {
  const float c = std::cos(radians), s = std::sin(radians);
  Mat3f r;
  r.m[1][1] = c; r.m[1][2] = -s; r.m[2][1] = s; r.m[2][2] = c;
  return r;
}
inline Mat3f rotation_y(float radians) {
  const float c = std::cos(radians), s = std::sin(radians);
  Mat3f r;
  r.m[0][0] = c; r.m[0][2] = s; r.m[2][0] = -s; r.m[2][2] = c;
  return r;
}
inline Mat3f rotation_z(float radians) {
  const float c = std::cos(radians), s = std::sin(radians);
  Mat3f r;
  r.m[0][0] = c; r.m[0][1] = -s; r.m[1][0] = s; r.m[1][1] = c;
  return r;
}

}  // namespace facetool
