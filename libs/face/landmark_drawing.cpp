// Box and landmark drawing, and resizing photos for contact sheets.
#include "libs/face/landmark_drawing.h"

#include <algorithm>
#include <cmath>

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

RgbImage resize_to_width(const RgbImage& image, int width) {
  const double scale = static_cast<double>(width) / image.width;
  RgbImage out;
  out.width = width;
  out.height = std::max(1, static_cast<int>(std::lround(image.height * scale)));
  out.pixels.resize(static_cast<size_t>(out.width) * out.height * 3);
  const int n = std::clamp(static_cast<int>(std::ceil(1.0 / scale)), 1, 16);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      float sum[3] = {0, 0, 0};
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          float s[3];
          sample_rgb_bilinear(image, (x - 0.5 + (i + 0.5) / n) / scale, (y - 0.5 + (j + 0.5) / n) / scale, s);
          for (int c = 0; c < 3; ++c) sum[c] += s[c];
        }
      for (int c = 0; c < 3; ++c) out.at(x, y)[c] = sum[c] / (n * n);
    }
  return out;
}

}  // namespace facetool
