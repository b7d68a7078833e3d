// The light's per-channel gain fitted to the photo: the scale of each colour of the network's light that best renders the crop.
#pragma once

#include <array>
#include <cstddef>

namespace facetool {

// A gain outside this range is taken as a degenerate crop (no light, a saturated or empty
// channel), not a colour of light: clamped. On the held-out photos and synthetic faces the
// fitted gains lay within 0.17-2.7, nine in ten within 0.8-1.3 (docs/photos.md, "The light's gain").
constexpr float kMinLightGain = 0.1f;
constexpr float kMaxLightGain = 10.0f;
// Fewer face pixels than this leave the light as it is (gain 1).
constexpr size_t kMinLightGainPixels = 50;

// For each colour c, the g_c minimising sum over the pixels p with mask[p] > 0.5 of
// (g_c reconstruction_c[p] - image_c[p])^2, i.e. <r_c, i_c> / <r_c, r_c>, clamped to
// [kMinLightGain, kMaxLightGain]; 1 where the mask holds fewer than kMinLightGainPixels pixels or
// the reconstruction is 0 there. Where the image's three channels are equal at every mask pixel
// (a grey photo), one gain for all three, minimising the sum over the colours: a grey photo says
// nothing of the light's colour, and a gain per colour would tint the light to undo the albedo's
// colour. `reconstruction` and `image` are [3][plane], `mask` [plane].
// The renderer is linear in the light, so scaling the light's channel c by g_c scales that
// channel's shading and reconstruction by g_c (apply_light_gain).
std::array<float, 3> fit_light_gain(const float* reconstruction, const float* image, const float* mask,
                                    size_t plane);

// Scales one face's light [27] (channel-major), shading and reconstruction ([3][plane] each) by
// the gains.
void apply_light_gain(const std::array<float, 3>& gain, float* light, float* shading, float* reconstruction,
                      size_t plane);

}  // namespace facetool
