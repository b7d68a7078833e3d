// Box and landmark drawing, and resizing photos for contact sheets.
#include "libs/face/landmark_drawing.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "libs/face/face_alignment.h"

namespace facetool {
namespace {

void put(RgbImage& image, int x, int y, const float colour[3]) {
  if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
  float* p = image.at(x, y);
  for (int c = 0; c < 3; ++c) p[c] = colour[c];
}

}  // namespace

void draw_face(RgbImage& image, const DetectedFace& face, double scale) {
  const float box[3] = {1.0f, 0.8f, 0.0f}, jaw[3] = {0.0f, 0.8f, 1.0f}, inner[3] = {1.0f, 0.05f, 0.05f};
  const int l = static_cast<int>(std::lround(face.left * scale)), r = static_cast<int>(std::lround(face.right * scale));
  const int t = static_cast<int>(std::lround(face.top * scale)), b = static_cast<int>(std::lround(face.bottom * scale));
  for (int x = l; x <= r; ++x) {
    put(image, x, t, box);
    put(image, x, b, box);
  }
  for (int y = t; y <= b; ++y) {
    put(image, l, y, box);
    put(image, r, y, box);
  }
  const int radius = std::max(1, static_cast<int>(std::lround((r - l) / 80.0)));
  for (int i = 0; i < kLandmarkCount; ++i) {
    const int cx = static_cast<int>(std::lround(face.landmarks[i].x * scale));
    const int cy = static_cast<int>(std::lround(face.landmarks[i].y * scale));
    for (int dy = -radius; dy <= radius; ++dy)
      for (int dx = -radius; dx <= radius; ++dx)
        if (dx * dx + dy * dy <= radius * radius)
          put(image, cx + dx, cy + dy, is_inner_landmark(i) ? inner : jaw);
  }
}

namespace {

// One output coordinate's n samples along an axis: source indices and bilinear weights, each
// sample clamped to the source as sample_rgb_bilinear clamps it.
struct AxisTaps {
  std::vector<int> lo, hi;
  std::vector<float> frac;
};

AxisTaps axis_taps(int out_size, int in_size, double scale, int n) {
  AxisTaps t;
  for (int o = 0; o < out_size; ++o)
    for (int i = 0; i < n; ++i) {
      const double u = std::clamp((o - 0.5 + (i + 0.5) / n) / scale, 0.0, in_size - 1.0);
      const int u0 = std::min(static_cast<int>(u), in_size - 1);
      t.lo.push_back(u0);
      t.hi.push_back(std::min(u0 + 1, in_size - 1));
      t.frac.push_back(static_cast<float>(u - u0));
    }
  return t;
}

}  // namespace

RgbImage resize_to_width(const RgbImage& image, int width) {
  // The mean of n x n bilinear samples per output pixel (n = the shrink factor, rounded up), done
  // as a pass along rows and a pass along columns: bilinear sampling with clamping is separable.
  const double scale = static_cast<double>(width) / image.width;
  RgbImage out;
  out.width = width;
  out.height = std::max(1, static_cast<int>(std::lround(image.height * scale)));
  out.pixels.resize(static_cast<size_t>(out.width) * out.height * 3);
  const int n = std::clamp(static_cast<int>(std::ceil(1.0 / scale)), 1, 16);
  const float inv_n = 1.0f / static_cast<float>(n);
  const AxisTaps tx = axis_taps(out.width, image.width, scale, n);
  const AxisTaps ty = axis_taps(out.height, image.height, scale, n);
  std::vector<float> rows(static_cast<size_t>(image.height) * out.width * 3);  // along x only
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      float sum[3] = {0, 0, 0};
      for (int i = x * n; i < (x + 1) * n; ++i) {
        const float *a = image.at(tx.lo[i], y), *b = image.at(tx.hi[i], y), f = tx.frac[i];
        for (int c = 0; c < 3; ++c) sum[c] += a[c] * (1 - f) + b[c] * f;
      }
      float* o = &rows[(static_cast<size_t>(y) * out.width + x) * 3];
      for (int c = 0; c < 3; ++c) o[c] = sum[c] * inv_n;
    }
  const size_t row_stride = static_cast<size_t>(out.width) * 3;
  for (int y = 0; y < out.height; ++y) {
    float* o = out.at(0, y);
    std::fill(o, o + row_stride, 0.0f);
    for (int j = y * n; j < (y + 1) * n; ++j) {
      const float *a = &rows[ty.lo[j] * row_stride], *b = &rows[ty.hi[j] * row_stride], f = ty.frac[j];
      for (size_t k = 0; k < row_stride; ++k) o[k] += a[k] * (1 - f) + b[k] * f;
    }
    for (size_t k = 0; k < row_stride; ++k) o[k] *= inv_n;
  }
  return out;
}

}  // namespace facetool
