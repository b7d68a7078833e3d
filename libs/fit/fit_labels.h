// Pseudo labels from the fit: a real face sample (prepare-real's EXR, with its crop landmarks)
// labelled with the fitted normals and visibility, the mask they hold in, and the light and albedo that least
// squares gives from its pixels (`facetool pseudo-label --from fit`; docs/fit.md).
#pragma once

#include <string>

#include "libs/fit/fit_shading.h"
#include "libs/fit/photo_fit.h"
#include "libs/io/layered_image.h"

namespace facetool {

// Which mask a fit-labelled sample carries (the region its losses and `eval` use).
enum class LabelMask {
  kTrusted,  // where every label holds: the fitted face inside the sample's own mask, eroded by one pixel
  kFitted,   // the whole fitted face region (before 2026-12-06; the shipped model's training labels)
};

// `sample` holds R G B (linear), mask and facetool:landmarks (136 crop-pixel numbers). Returns
// the sample with channels albedo.R/G/B, normal.X/Y/Z (smoothed by options.render's
// normal_smoothing), visibility.0..8 added (replaced if present), mask replaced by `mask`'s
// region (with kFitted about 40 % of it lies outside the trusted pixels, where the albedo label
// is 0 and the photo may be the fill beyond its edge), the fitted mesh's own (unsmoothed) normals
// as the input prior prior.X/Y/Z (libs/fit/fit_prior.h; only when the fit's settings make one:
// input_prior_name), facetool:light_sh (27 numbers) and facetool:pseudo_labels = `label`; other
// channels and attributes kept. Throws facetool::Error naming `source` when the sample lacks
// landmarks or colour channels.
LayeredImage fit_labelled_sample(const LayeredImage& sample, const std::string& source, const FitBasis& basis,
                                 const PhotoFitOptions& options, const VisibilitySampler& sampler,
                                 const std::string& label, LabelMask mask = LabelMask::kTrusted);

}  // namespace facetool
