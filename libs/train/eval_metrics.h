// Evaluation metrics in the face mask: normal angular error, PSNR, SSIM, E_L of two lights.
#pragma once

#include <cstdint>
#include <vector>

namespace facetool {

// Angles in degrees between predicted and true normals ([3][plane] each, any length) at the
// pixels where mask > 0.5, appended to `angles`.
void normal_angles_deg(const float* predicted, const float* truth, const float* mask,
                       int64_t plane, std::vector<double>& angles);

// Table 1 of the paper from all angles: mean, standard deviation, % under 20, 25, 30 degrees.
struct AngularSummary {
  int64_t pixels = 0;
  double mean = 0, std = 0, under20 = 0, under25 = 0, under30 = 0;
};
AngularSummary summarize_angles(const std::vector<double>& angles);

// The sufficient statistics of a set of angles, so that sets summarised apart (images, eval
// shards) merge into the summary of their union: summarize_angles is AngleSums over its angles.
struct AngleSums {
  int64_t pixels = 0, under20 = 0, under25 = 0, under30 = 0;
  double sum = 0, sum_sq = 0;
  void add(double angle_deg);
  void add(const AngleSums& other);
  AngularSummary summary() const;
};

// Mean over masked pixels and the `channels` planes of (a - b)^2.
double masked_mse(const float* a, const float* b, const float* mask, int channels, int64_t plane);

// 10 log10(1 / MSE) over the masked pixels of 3-channel images (linear values, peak 1);
// +infinity for identical images.
double masked_psnr(const float* a, const float* b, const float* mask, int width, int height);

// SSIM (Wang et al. 2004: 7x7 uniform window, C1 = 0.01^2, C2 = 0.03^2, peak 1) per channel,
// averaged over the 3 channels and over the masked pixels whose whole window is inside the image.
double masked_ssim(const float* a, const float* b, const float* mask, int width, int height);

// E_L of two [27] lights: mean over the 3 channels and 64,000 Fibonacci directions of the squared
// difference of their values (the paper's light loss for one image).
double light_error(const float* a, const float* b);

}  // namespace facetool
