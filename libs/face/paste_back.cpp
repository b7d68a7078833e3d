// Paste-back region (mask distance to alpha) and bilinear blending into the photo.
#include "libs/face/paste_back.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "libs/face/face_mask.h"
#include "core/util/error.h"
#include "core/util/parallel_for.h"
#include "core/util/stage_timer.h"

namespace facetool {

PasteRegion paste_region(int photo_width, int photo_height, const Similarity2& photo_to_crop,
                         int crop_size, const std::vector<Point2>& polygon, double feather) {
  check(polygon.size() >= 3, "paste-back: the face mask has fewer than 3 corners");
  const Similarity2 back = photo_to_crop.inverse();
  double lx = 1e300, ly = 1e300, hx = -1e300, hy = -1e300;
  for (const Point2& c : polygon) {
    const Point2 p = back.apply(c);
    lx = std::min(lx, p.x);
    ly = std::min(ly, p.y);
    hx = std::max(hx, p.x);
    hy = std::max(hy, p.y);
  }
  PasteRegion r;
  r.photo_to_crop = photo_to_crop;
  r.crop_size = crop_size;
  r.x0 = std::clamp(static_cast<int>(std::floor(lx)) - 1, 0, photo_width);
  r.y0 = std::clamp(static_cast<int>(std::floor(ly)) - 1, 0, photo_height);
  const int x1 = std::clamp(static_cast<int>(std::ceil(hx)) + 2, 0, photo_width);
  const int y1 = std::clamp(static_cast<int>(std::ceil(hy)) + 2, 0, photo_height);
  r.width = std::max(0, x1 - r.x0);
  r.height = std::max(0, y1 - r.y0);
  r.alpha.assign(static_cast<size_t>(r.width) * r.height, 0.0f);
  const ConvexInterior interior(polygon);
  parallel_for(r.height, 16, [&](int64_t begin, int64_t end) {
  for (int y = static_cast<int>(begin); y < end; ++y)
    for (int x = 0; x < r.width; ++x) {
      const Point2 c = photo_to_crop.apply({static_cast<double>(r.x0 + x), static_cast<double>(r.y0 + y)});
      const double d = feather > 0 ? interior.depth(c)
                                   : signed_distance_inside(polygon, c);
      const double a = feather > 0 ? d / feather : (d >= 0 ? 1.0 : 0.0);
      r.alpha[static_cast<size_t>(y) * r.width + x] = static_cast<float>(std::clamp(a, 0.0, 1.0));
    }
  });
  return r;
}

namespace {

// One photo pixel's bilinear tap into the crop, computed once for all channels.
struct Tap {
  size_t at;          // the photo pixel
  uint32_t i00;       // its top-left crop sample
  uint32_t dx, dy;    // steps to the right and lower samples (0 at the crop's last column, row)
  float fx, fy, a;    // bilinear weights and the blend weight
};

}  // namespace

void paste_channels(const PasteRegion& r, const float* crop, int channels, float* photo,
                    int photo_width, int photo_height) {
  StageTimer timer("paste-back");
  const int s = r.crop_size;
  const size_t crop_plane = static_cast<size_t>(s) * s;
  const size_t photo_plane = static_cast<size_t>(photo_width) * photo_height;
  parallel_for(r.height, 16, [&](int64_t begin, int64_t end) {
    std::vector<Tap> taps;
    taps.reserve(static_cast<size_t>(end - begin) * r.width);
    for (int y = static_cast<int>(begin); y < end; ++y)
      for (int x = 0; x < r.width; ++x) {
        const float a = r.alpha[static_cast<size_t>(y) * r.width + x];
        if (a <= 0) continue;
        const int px = r.x0 + x, py = r.y0 + y;
        const Point2 c = r.photo_to_crop.apply({static_cast<double>(px), static_cast<double>(py)});
        const double cx = std::clamp(c.x, 0.0, s - 1.0), cy = std::clamp(c.y, 0.0, s - 1.0);
        const int x0 = std::min(static_cast<int>(cx), s - 1), y0 = std::min(static_cast<int>(cy), s - 1);
        taps.push_back({static_cast<size_t>(py) * photo_width + px, static_cast<uint32_t>(y0 * s + x0),
                        static_cast<uint32_t>(x0 + 1 < s ? 1 : 0), static_cast<uint32_t>(y0 + 1 < s ? s : 0),
                        static_cast<float>(cx - x0), static_cast<float>(cy - y0), a});
      }
    // Channel by channel: each pass reads one crop plane and writes one photo plane.
    for (int k = 0; k < channels; ++k) {
      const float* p = crop + k * crop_plane;
      float* o = photo + k * photo_plane;
      for (const Tap& t : taps) {
        const float* q = p + t.i00;
        const float v = (q[0] * (1 - t.fx) + q[t.dx] * t.fx) * (1 - t.fy) +
                        (q[t.dy] * (1 - t.fx) + q[t.dy + t.dx] * t.fx) * t.fy;
        o[t.at] = t.a * v + (1 - t.a) * o[t.at];
      }
    }
  });
}

}  // namespace facetool
