// A real photo's albedo unwrapped into the neutral face's texture frame through the landmark fit
// (`facetool unwrap`), for photo-textured synthetic faces (libs/synth/albedo_texture.h).
#pragma once

#include <string>

#include "libs/fit/landmark_fit.h"
#include "libs/io/layered_image.h"
#include "libs/synth/albedo_texture.h"

namespace facetool {

struct UnwrapSettings {
  // Pixels whose fitted normal is turned further than this from the camera (n_z below it) are
  // not used: grazing views stretch and shade badly.
  float min_facing = 0.3f;
  // Pixels whose shading (the renderer's sum_i L_ci transfer_i / pi, per channel) is below this
  // are not used: the division by it would amplify noise in shadow.
  float min_shading = 0.05f;
  float max_albedo = 1.0f;  // the de-lit albedo is clamped to [0, max_albedo]
  // Gaussian of this many texels spreading each texel's samples over its neighbours (fills the
  // gaps between the photo's pixels where the texture is finer).
  float spread_texels = 0.8f;
};

// `sample` holds R G B (linear), mask, normal.X/Y/Z, visibility.0..8, facetool:light_sh and
// facetool:landmarks: a fit-labelled real sample (`pseudo-label --from fit`) or a synthetic one.
// The fit of its landmarks (`fit`, the settings the labels were made with) says which point of
// the neutral face each pixel shows; each pixel of the mask is de-lit by its shading
// (albedo_c = pi I_c / sum_i L_ci transfer_i, from the sample's normals, visibility and light)
// and splatted into the texture, weighted by its facing (n_z). The weight of a texel is the
// splatted weight, spread and clamped to [0, 1]. Throws facetool::Error naming `source` when a
// channel, the light or the landmarks are missing.
AlbedoTexture unwrap_albedo(const LayeredImage& sample, const std::string& source, const FitBasis& basis,
                            const FitSettings& fit, const AlbedoTextureFrame& frame,
                            const UnwrapSettings& settings = {});

}  // namespace facetool
