// Resizing planar float images with per-axis weight tables.
#include "libs/image/resize.h"

#include <algorithm>
#include <cmath>

#include "core/util/error.h"

namespace facetool {
namespace {

struct Tap {
  int index;
  float weight;
};

// For each output position along one axis, the source positions and weights that make it.
std::vector<std::vector<Tap>> axis_weights(int in, int out) {
  std::vector<std::vector<Tap>> taps(static_cast<size_t>(out));
  const double scale = static_cast<double>(in) / out;
  for (int o = 0; o < out; ++o) {
    if (out < in) {
      // Output pixel o covers source interval [o * scale, (o + 1) * scale).
      const double lo = o * scale, hi = (o + 1) * scale;
      for (int i = static_cast<int>(std::floor(lo)); i < std::min(in, static_cast<int>(std::ceil(hi))); ++i) {
        const double overlap = std::min<double>(hi, i + 1) - std::max<double>(lo, i);
        if (overlap > 0) taps[o].push_back({i, static_cast<float>(overlap / scale)});
      }
    } else {
      const double src = std::max(0.0, (o + 0.5) * scale - 0.5);
      const int i0 = std::min(static_cast<int>(src), in - 1);
      const int i1 = std::min(i0 + 1, in - 1);
      const float t = static_cast<float>(src - i0);
      taps[o].push_back({i0, 1.0f - t});
      if (t > 0) taps[o].push_back({i1, t});
    }
  }
  return taps;
}

}  // namespace

std::vector<float> resize_planar(const std::vector<float>& src, int channels, int width,
                                 int height, int out_width, int out_height) {
  check(width > 0 && height > 0 && out_width > 0 && out_height > 0, "resize: invalid sizes ",
        width, "x", height, " -> ", out_width, "x", out_height);
  check(src.size() == static_cast<size_t>(channels) * width * height, "resize: expected ",
        channels, " planes of ", width, "x", height, " values, got ", src.size());
  if (width == out_width && height == out_height) return src;
  const auto tx = axis_weights(width, out_width);
  const auto ty = axis_weights(height, out_height);
  std::vector<float> rows(static_cast<size_t>(channels) * height * out_width);
  for (int c = 0; c < channels; ++c)
    for (int y = 0; y < height; ++y) {
      const float* in = src.data() + (static_cast<size_t>(c) * height + y) * width;
      float* out = rows.data() + (static_cast<size_t>(c) * height + y) * out_width;
      for (int x = 0; x < out_width; ++x) {
        float v = 0;
        for (const Tap& t : tx[x]) v += t.weight * in[t.index];
        out[x] = v;
      }
    }
  std::vector<float> dst(static_cast<size_t>(channels) * out_height * out_width, 0.0f);
  for (int c = 0; c < channels; ++c)
    for (int y = 0; y < out_height; ++y) {
      float* out = dst.data() + (static_cast<size_t>(c) * out_height + y) * out_width;
      for (const Tap& t : ty[y]) {
        const float* in = rows.data() + (static_cast<size_t>(c) * height + t.index) * out_width;
        for (int x = 0; x < out_width; ++x) out[x] += t.weight * in[x];
      }
    }
  return dst;
}

}  // namespace facetool
