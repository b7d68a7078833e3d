// Relighting decomposed photos: per new light, one render of every face and a paste-back
// (`facetool relight`, docs/relighting.md).
#pragma once

#include <string>
#include <vector>

#include "libs/photo/photo_pipeline.h"
#include "libs/relight/relight_math.h"
#include "core/sh/sh_types.h"

namespace facetool {

struct RelightSettings {
  relight::Mode mode = relight::Mode::Ratio;
  float ratio_epsilon = relight::kDefaultRatioEpsilon;
  bool visibility = true;  // false: open hemisphere (--no-visibility)
};

// One relit photo at the photo's resolution (linear RGB) and the new shading (1 outside faces).
struct RelitPhoto {
  RgbImage image;
  std::vector<float> new_shading;  // [3][w*h]
};

// Replaces every face's light by `light` (photo frame): one render of all faces and a paste-back,
// no network pass.
RelitPhoto relight_photo(const DecomposedPhoto& photo, const sh::RgbLight& light,
                         const RelightSettings& settings, RendererPlugin& renderer, Backend& backend);

// The photo's estimated shading [3][w*h], 1 where no face is: its pasted shading layer is
// premultiplied by the faces' coverage alpha (pasted over 0), so this is that layer + 1 - alpha.
std::vector<float> estimated_shading(const DecomposedPhoto& photo);

// A planar shading layer shown over the photo (the photo where no face is), for sheets.
RgbImage shading_over_photo(const DecomposedPhoto& photo, const std::vector<float>& shading);

// Tiles scaled to `height` pixels and set side by side with a 2-pixel gap.
RgbImage side_by_side(const std::vector<RgbImage>& tiles, int height);

// The light's lit sphere: the left square of its preview (light_preview.h), size x size.
RgbImage light_sphere(const sh::RgbLight& light, int size);

// light_sphere() drawn into the image's top-right corner.
void draw_light_sphere(RgbImage& image, const sh::RgbLight& light, int size);

}  // namespace facetool
