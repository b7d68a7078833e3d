// Mirror averaging: the mirrored batch in, the two answers combined (docs/photos.md, "Mirror averaging").
#include "libs/inference/mirror_average.h"

#include <algorithm>
#include <cmath>

#include "core/sh/sh_basis.h"
#include "core/util/error.h"

namespace facetool {
namespace {

// Plane `src` (S x S) flipped left to right and scaled by `sign`, added into `dst` with weight 1/2,
// after `dst` was scaled by 1/2.
void average_flipped_plane(float* dst, const float* src, int size, float sign) {
  for (int y = 0; y < size; ++y) {
    float* d = dst + static_cast<size_t>(y) * size;
    const float* s = src + static_cast<size_t>(y) * size;
    for (int x = 0; x < size; ++x) d[x] = 0.5f * d[x] + 0.5f * sign * s[size - 1 - x];
  }
}

// The first `count` images' planes averaged with the mirrored planes of the next `count`.
std::vector<float> average_maps(const std::vector<float>& both, int count, int planes, int size,
                                float (*sign)(int plane)) {
  const size_t plane = static_cast<size_t>(size) * size;
  const size_t image = plane * planes;
  check(both.size() == image * 2 * count, "mirror average: expected ", 2 * count, " maps of ",
        planes, " planes");
  std::vector<float> out(both.begin(), both.begin() + image * count);
  for (int n = 0; n < count; ++n)
    for (int c = 0; c < planes; ++c)
      average_flipped_plane(out.data() + n * image + c * plane,
                            both.data() + (count + n) * image + c * plane, size, sign(c));
  return out;
}

float keep_sign(int) { return 1.0f; }
float normal_sign(int channel) { return channel == 0 ? -1.0f : 1.0f; }
float sh_sign(int coefficient) { return static_cast<float>(sh::mirror_x_sign(coefficient)); }

}  // namespace

std::vector<float> with_mirror_images(const std::vector<float>& images, int count, int channels,
                                      int size, int normal_channel) {
  const size_t plane = static_cast<size_t>(size) * size;
  const size_t image = plane * channels;
  check(images.size() == image * count, "mirror average: expected ", count, " images of ",
        channels, " channels");
  std::vector<float> out(images.size() * 2);
  std::copy(images.begin(), images.end(), out.begin());
  for (int n = 0; n < count; ++n)
    for (int c = 0; c < channels; ++c) {
      const float sign = c == normal_channel ? -1.0f : 1.0f;
      const float* src = images.data() + n * image + c * plane;
      float* dst = out.data() + (count + n) * image + c * plane;
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
          dst[static_cast<size_t>(y) * size + x] = sign * src[static_cast<size_t>(y) * size + size - 1 - x];
    }
  return out;
}

NetworkAnswer average_with_mirror(const NetworkAnswer& both, int count, int size) {
  NetworkAnswer out;
  out.albedo = average_maps(both.albedo, count, 3, size, keep_sign);
  out.normal = average_maps(both.normal, count, 3, size, normal_sign);
  out.visibility = average_maps(both.visibility, count, 9, size, sh_sign);
  const size_t plane = static_cast<size_t>(size) * size;
  for (int n = 0; n < count; ++n) {
    float* normal = out.normal.data() + n * 3 * plane;
    for (size_t p = 0; p < plane; ++p) {
      const float x = normal[p], y = normal[plane + p], z = normal[2 * plane + p];
      const float length = std::sqrt(x * x + y * y + z * z);
      if (length < 1e-8f) continue;  // opposite answers: left at 0, rendered 0 (conventions.md)
      normal[p] = x / length;
      normal[plane + p] = y / length;
      normal[2 * plane + p] = z / length;
    }
  }
  check(both.light.size() == static_cast<size_t>(2 * count) * 27, "mirror average: expected ",
        2 * count, " lights");
  out.light.assign(both.light.begin(), both.light.begin() + count * 27);
  for (int n = 0; n < count; ++n)
    for (int k = 0; k < 27; ++k)
      out.light[n * 27 + k] = 0.5f * out.light[n * 27 + k] +
                              0.5f * sh_sign(k % 9) * both.light[(count + n) * 27 + k];
  return out;
}

}  // namespace facetool
