// A Gaussian blur of planar float images (eval's blurred-photo baseline, unwrapping, fit normals).
#pragma once

#include <vector>

namespace facetool {

// Blurs each of `channels` planes of width x height with a Gaussian of standard deviation
// `sigma` pixels, separably (rows, then columns), its kernel cut at 3 sigma and normalised
// to sum 1; at the image's edges the kernel is cut and renormalised over the pixels inside
// (no edge repetition, no zeros). sigma = 0 returns the image unchanged. Throws
// facetool::Error on a size mismatch, a negative or non-finite sigma.
std::vector<float> gaussian_blur(const std::vector<float>& image, int channels, int width,
                                 int height, double sigma);

}  // namespace facetool
