// Guided paste-back: the face's guide, coefficients fitted on the crop's grid, applied at the
// photo's pixels.
#include "libs/face/guided_paste.h"

#include <algorithm>
#include <cmath>

#include "core/util/error.h"
#include "core/util/stage_timer.h"
#include "libs/face/face_alignment.h"
#include "libs/image/guided_filter.h"
#include "libs/io/image_io.h"

namespace facetool {

FaceGuide face_guide(const RgbImage& photo, const PasteRegion& r) {
  StageTimer timer("guided filter");
  const int w = photo.width, h = photo.height;
  check(w > 0 && h > 0 && r.crop_size > 0, "guided paste-back: an empty photo or crop");
  // The photo pixels the crop's samples can touch (its corners mapped back, one pixel of margin
  // for bilinear taps) and the paste region's box; clipped to the photo, where edge repeat then
  // clamps as it would on the whole photo.
  const Similarity2 back = r.photo_to_crop.inverse();
  const double s = r.crop_size;
  double lx = r.x0, ly = r.y0, hx = r.x0 + r.width - 1.0, hy = r.y0 + r.height - 1.0;
  for (const Point2 c : {Point2{-0.5, -0.5}, Point2{s - 0.5, -0.5}, Point2{-0.5, s - 0.5}, Point2{s - 0.5, s - 0.5}}) {
    const Point2 p = back.apply(c);
    lx = std::min(lx, p.x - 1);
    ly = std::min(ly, p.y - 1);
    hx = std::max(hx, p.x + 1);
    hy = std::max(hy, p.y + 1);
  }
  FaceGuide g;
  g.x0 = std::clamp(static_cast<int>(std::floor(lx)), 0, w - 1);
  g.y0 = std::clamp(static_cast<int>(std::floor(ly)), 0, h - 1);
  g.width = std::clamp(static_cast<int>(std::ceil(hx)) + 1, g.x0 + 1, w) - g.x0;
  g.height = std::clamp(static_cast<int>(std::ceil(hy)) + 1, g.y0 + 1, h) - g.y0;
  g.photo.resize(static_cast<size_t>(g.width) * g.height);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const float* p = photo.at(g.x0 + x, g.y0 + y);
      g.photo[static_cast<size_t>(y) * g.width + x] =
          std::clamp(luminance(linear_to_srgb(p[0]), linear_to_srgb(p[1]), linear_to_srgb(p[2])), 0.0f, 1.0f);
    }
  g.crop = warp_plane_to_crop(g.photo.data(), g.width, g.height,
                              r.photo_to_crop.then_after(Similarity2::from(1.0, 0.0, g.x0, g.y0)), r.crop_size);
  return g;
}

void paste_channels_guided(const PasteRegion& r, const float* crop, int channels, const FaceGuide& guide,
                           float* photo, int photo_width, int photo_height, bool unit_vectors,
                           float clamp_lo, float clamp_hi, const GuidedUpsampling& settings) {
  const size_t photo_plane = static_cast<size_t>(photo_width) * photo_height;
  const int s = r.crop_size;
  const size_t crop_plane = static_cast<size_t>(s) * s;
  check(channels >= 1 && channels <= 16, "guided paste-back: 1 to 16 channels, not ", channels);
  check(!unit_vectors || channels == 3, "guided paste-back: unit vectors need 3 channels, not ", channels);
  check(guide.crop.size() == crop_plane, "guided paste-back: a crop guide of ", guide.crop.size(),
        " pixels for a ", s, "x", s, " crop");
  if (r.width == 0 || r.height == 0) return;
  check(r.x0 >= guide.x0 && r.y0 >= guide.y0 && r.x0 + r.width <= guide.x0 + guide.width &&
            r.y0 + r.height <= guide.y0 + guide.height,
        "guided paste-back: the guide does not cover the paste region (made for another face?)");
  // a and b on the crop's grid.
  std::vector<float> coefficients;  // [2C][S*S]: a then b
  {
    StageTimer timer("guided filter");
    const GuidedCoefficients k = guided_coefficients(
        guide.crop, std::vector<float>(crop, crop + channels * crop_plane), channels, s, s,
        settings.radius, settings.epsilon);
    coefficients = k.a;
    coefficients.insert(coefficients.end(), k.b.begin(), k.b.end());
  }
  // Both sampled bilinearly over the region's box: paste_channels with alpha 1 into a box image.
  const size_t box = static_cast<size_t>(r.width) * r.height;
  PasteRegion whole = r;
  whole.x0 = 0;
  whole.y0 = 0;
  whole.alpha.assign(box, 1.0f);
  whole.photo_to_crop = r.photo_to_crop.then_after(Similarity2::from(1.0, 0.0, r.x0, r.y0));
  std::vector<float> ab(box * 2 * channels, 0.0f);
  paste_channels(whole, coefficients.data(), 2 * channels, ab.data(), r.width, r.height);
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x) {
      const size_t i = static_cast<size_t>(y) * r.width + x;
      const float alpha = r.alpha[i];
      if (alpha <= 0) continue;
      const float I = guide.photo[static_cast<size_t>(r.y0 + y - guide.y0) * guide.width + (r.x0 + x - guide.x0)];
      float v[16];
      for (int k = 0; k < channels; ++k) v[k] = ab[k * box + i] * I + ab[(channels + k) * box + i];
      if (unit_vectors) {
        const float n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        for (int k = 0; k < 3 && n > 0; ++k) v[k] /= n;
      } else {
        for (int k = 0; k < channels; ++k) v[k] = std::clamp(v[k], clamp_lo, clamp_hi);
      }
      const size_t at = static_cast<size_t>(r.y0 + y) * photo_width + r.x0 + x;
      for (int k = 0; k < channels; ++k) {
        float& o = photo[k * photo_plane + at];
        o = alpha * v[k] + (1 - alpha) * o;
      }
    }
}

}  // namespace facetool
