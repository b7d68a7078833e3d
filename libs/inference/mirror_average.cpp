// Mirror averaging: the mirrored batch in, the two answers combined (docs/photos.md, "Mirror averaging").
#include "libs/inference/mirror_average.h"

#include <algorithm>
#include <cmath>

#include "core/sh/sh_basis.h"
#include "core/util/error.h"
#include "libs/image/mirror.h"

namespace facetool {
namespace {

// The first `count` images' planes averaged with the mirrored planes of the next `count`.
std::vector<float> average_maps(const std::vector<float>& both, int count, int planes, int size,
                                float (*sign)(int plane)) {
  const size_t plane = static_cast<size_t>(size) * size;
  const size_t image = plane * planes;
  check(both.size() == image * 2 * count, "mirror average: expected ", 2 * count, " maps of ",
        planes, " planes");
  std::vector<float> out(both.begin(), both.begin() + image * count);
  std::vector<float> back(both.begin() + image * count, both.end());
  for (int n = 0; n < count; ++n)
    for (int c = 0; c < planes; ++c) mirror_plane(back.data() + n * image + c * plane, size, size, sign(c));
  for (size_t k = 0; k < out.size(); ++k) out[k] = 0.5f * out[k] + 0.5f * back[k];
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
  std::copy(images.begin(), images.end(), out.begin() + images.size());
  for (int n = 0; n < count; ++n)
    for (int c = 0; c < channels; ++c)
      mirror_plane(out.data() + (count + n) * image + c * plane, size, size, c == normal_channel ? -1.0f : 1.0f);
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
