// The fit's normals as a network's input prior: channels prior.X/Y/Z added to a sample from the
// ICT-FaceKit fit to its crop landmarks (`facetool pseudo-label --from fit`; docs/fit.md).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "libs/fit/landmark_fit.h"
#include "libs/fit/photo_fit.h"
#include "libs/io/layered_image.h"

namespace facetool {

// The sample's crop landmarks (facetool:landmarks, 136 numbers: prepare-real's samples and synth's
// since it writes them) as a fit target of the sample's size. Throws facetool::Error naming
// `source` when they are missing or malformed.
LandmarkTarget read_sample_landmarks(const LayeredImage& sample, const std::string& source);

// Moves every landmark by a normal deviate of standard deviation `sigma_px` in x and in y, drawn
// from `seed`.
Landmarks68 add_landmark_noise(const Landmarks68& landmarks, double sigma_px, uint64_t seed);

// Moves every landmark by a normal deviate of standard deviation `fraction` x the inter-ocular
// distance (between the centres of points 36-41 and 42-47) in x and in y, drawn from `seed`: a
// detector's error, for synthetic samples whose landmarks are exact.
Landmarks68 jitter_landmarks(const Landmarks68& landmarks, double fraction, uint64_t seed);

// The fit settings of an input prior (NetworkConfig::input_prior): "fit_normal" is the default
// fit, "fit_normal fov F" the default fit with F degrees over the crop. Throws facetool::Error for
// another prior.
FitSettings prior_fit_settings(const std::string& input_prior);
// The input prior a fit with `settings` gives: "fit_normal" for the defaults, "fit_normal fov F"
// when only the field of view differs; "" when other settings differ (such a prior could not be
// made again for a photo, so it is not one).
std::string input_prior_name(const FitSettings& settings);

// `sample` with planar normals [3][plane] (the fit's, 0 off the fitted head) as channels
// prior.X/Y/Z, replacing them when present, and facetool:input_prior = `input_prior` (the name of
// the fit that made them), facetool:prior_landmark_noise = `landmark_noise`; other channels and
// attributes kept.
LayeredImage with_prior_channels(const LayeredImage& sample, const std::vector<float>& normals,
                                 double landmark_noise, const std::string& input_prior);

// The prior itself: the fit of `target` (a crop's landmarks at the crop's size) rendered without
// visibility: planar normals [3][width * height], camera frame, 0 off the fitted head. The same
// for training samples and for photos (infer, relight).
std::vector<float> fit_prior_normals(const FitBasis& basis, const LandmarkTarget& target,
                                     const FitSettings& settings = FitSettings{});

// `sample` (with crop landmarks) with the prior channels of the fit to its landmarks, jittered by
// `landmark_noise` (jitter_landmarks, seeded by `seed`) when it is > 0; labels and attributes
// kept, facetool:input_prior = input_prior_name(settings) and facetool:prior_landmark_noise added.
// No visibility is cast. Throws facetool::Error naming `source` when the sample lacks landmarks,
// and when `settings` make no input prior (input_prior_name).
LayeredImage fit_prior_sample(const LayeredImage& sample, const std::string& source, const FitBasis& basis,
                              const FitSettings& settings, double landmark_noise, uint64_t seed);

}  // namespace facetool
