// The guided filter (He, Sun and Tang, "Guided Image Filtering", ECCV 2010 / TPAMI 2013) with a
// grey guide: edge-aware smoothing and upsampling of planar float images.
#pragma once

#include <vector>

namespace facetool {

// For each (2r+1)^2 window w_k (clipped at the image's edges) the linear model q = a_k I + b_k
// that best fits the target p in the least-squares sense with ridge `epsilon`:
//   a_k = cov_k(I, p) / (var_k(I) + epsilon),  b_k = mean_k(p) - a_k mean_k(I),
// and q_i = mean over the windows holding i of a_k I_i + b_k. Where the guide has an edge the
// output follows it (a ~ cov/var); where the guide is flat (var << epsilon) q is the box mean of
// p. Box sums by summed-area tables (double), O(1) per pixel. `guide` [w*h]; `target` and the
// result `channels` planes of w*h. Throws facetool::Error on mismatched sizes, r < 0, eps <= 0.
std::vector<float> guided_filter(const std::vector<float>& guide, const std::vector<float>& target,
                                 int channels, int width, int height, int radius, double epsilon);

// The filter's averaged coefficients: `a` and `b` (`channels` planes of w*h each) with
// guided_filter(...) = a * guide + b per pixel. Upsampling (He and Sun, "Fast Guided Filter",
// 2015) computes them on a coarse grid, resamples them to the fine one and applies them there
// to the fine guide, so edges of the fine guide appear in the result.
struct GuidedCoefficients {
  std::vector<float> a, b;
};
GuidedCoefficients guided_coefficients(const std::vector<float>& guide, const std::vector<float>& target,
                                       int channels, int width, int height, int radius, double epsilon);

}  // namespace facetool
