// Guided paste-back: coefficients fitted on the crop's grid, applied at the photo's pixels.
#include "libs/face/guided_paste.h"

#include <algorithm>
#include <cmath>

#include "core/util/error.h"
#include "core/util/stage_timer.h"
#include "libs/face/face_alignment.h"
#include "libs/image/guided_filter.h"

namespace facetool {

std::vector<float> photo_guide(const RgbImage& photo) {
  const size_t plane = static_cast<size_t>(photo.width) * photo.height;
  std::vector<float> guide(plane);
  for (size_t i = 0; i < plane; ++i) {
    const float* p = photo.pixels.data() + 3 * i;
    guide[i] = std::clamp(0.2126f * linear_to_srgb(p[0]) + 0.7152f * linear_to_srgb(p[1]) +
                              0.0722f * linear_to_srgb(p[2]),
                          0.0f, 1.0f);
  }
  return guide;
}

std::vector<float> crop_guide(const std::vector<float>& guide, int w, int h, const PasteRegion& r) {
  StageTimer timer("guided filter");
  check(guide.size() == static_cast<size_t>(w) * h, "guided paste-back: a guide of ", guide.size(),
        " pixels for a ", w, "x", h, " photo");
  // The photo pixels the crop's samples can touch: its corners mapped back, one pixel of margin
  // for bilinear taps; clipped to the photo (where edge repeat then clamps as on the whole photo).
  const Similarity2 back = r.photo_to_crop.inverse();
  const double s = r.crop_size;
  double lx = 1e300, ly = 1e300, hx = -1e300, hy = -1e300;
  for (const Point2 c : {Point2{-0.5, -0.5}, Point2{s - 0.5, -0.5}, Point2{-0.5, s - 0.5}, Point2{s - 0.5, s - 0.5}}) {
    const Point2 p = back.apply(c);
    lx = std::min(lx, p.x);
    ly = std::min(ly, p.y);
    hx = std::max(hx, p.x);
    hy = std::max(hy, p.y);
  }
  const int x0 = std::clamp(static_cast<int>(std::floor(lx)) - 1, 0, w - 1);
  const int y0 = std::clamp(static_cast<int>(std::floor(ly)) - 1, 0, h - 1);
  const int x1 = std::clamp(static_cast<int>(std::ceil(hx)) + 2, x0 + 1, w);
  const int y1 = std::clamp(static_cast<int>(std::ceil(hy)) + 2, y0 + 1, h);
  RgbImage part;
  part.width = x1 - x0;
  part.height = y1 - y0;
  part.pixels.resize(static_cast<size_t>(part.width) * part.height * 3);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      std::fill_n(part.at(x - x0, y - y0), 3, guide[static_cast<size_t>(y) * w + x]);
  std::vector<float> out = warp_to_crop(part, r.photo_to_crop.then_after(Similarity2::from(1.0, 0.0, x0, y0)), r.crop_size);
  out.resize(static_cast<size_t>(r.crop_size) * r.crop_size);  // the first of three equal planes
  return out;
}

void paste_channels_guided(const PasteRegion& r, const float* crop, int channels,
                           const std::vector<float>& crop_guide_planar,
                           const std::vector<float>& guide, float* photo, int photo_width,
                           int photo_height, bool unit_vectors, float clamp_lo, float clamp_hi,
                           const GuidedUpsampling& settings) {
  const size_t photo_plane = static_cast<size_t>(photo_width) * photo_height;
  check(guide.size() == photo_plane, "guided paste-back: a guide of ", guide.size(), " pixels for a ",
        photo_width, "x", photo_height, " photo");
  check(channels >= 1 && channels <= 16, "guided paste-back: 1 to 16 channels, not ", channels);
  check(!unit_vectors || channels == 3, "guided paste-back: unit vectors need 3 channels, not ", channels);
  if (r.width == 0 || r.height == 0) return;
  const int s = r.crop_size;
  const size_t crop_plane = static_cast<size_t>(s) * s;
  check(crop_guide_planar.size() == crop_plane, "guided paste-back: a crop guide of ",
        crop_guide_planar.size(), " pixels for a ", s, "x", s, " crop");
  // a and b on the crop's grid, against the guide warped into the crop as the photo was.
  std::vector<float> coefficients;  // [2C][S*S]: a then b
  {
    StageTimer timer("guided filter");
    const GuidedCoefficients k = guided_coefficients(
        crop_guide_planar, std::vector<float>(crop, crop + channels * crop_plane), channels, s, s,
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
      const size_t at = static_cast<size_t>(r.y0 + y) * photo_width + r.x0 + x;
      float v[16];
      for (int k = 0; k < channels; ++k) v[k] = ab[k * box + i] * guide[at] + ab[(channels + k) * box + i];
      if (unit_vectors) {
        const float n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        for (int k = 0; k < 3 && n > 0; ++k) v[k] /= n;
      } else {
        for (int k = 0; k < channels; ++k) v[k] = std::clamp(v[k], clamp_lo, clamp_hi);
      }
      for (int k = 0; k < channels; ++k) {
        float& o = photo[k * photo_plane + at];
        o = alpha * v[k] + (1 - alpha) * o;
      }
    }
}

}  // namespace facetool
