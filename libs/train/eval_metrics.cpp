// Masked metrics for `facetool eval`: angles, PSNR, SSIM, light error.
#include "libs/train/eval_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/sh/sh_gram.h"
#include "core/util/math_constants.h"

namespace facetool {

void normal_angles_deg(const float* p, const float* t, const float* mask, int64_t plane,
                       std::vector<double>& angles) {
  const double kDegrees = 180.0 / kPi;
  for (int64_t i = 0; i < plane; ++i) {
    if (mask[i] <= 0.5f) continue;
    double dot = 0, lp = 0, lt = 0;
    for (int c = 0; c < 3; ++c) {
      dot += double(p[c * plane + i]) * t[c * plane + i];
      lp += double(p[c * plane + i]) * p[c * plane + i];
      lt += double(t[c * plane + i]) * t[c * plane + i];
    }
    const double denom = std::sqrt(lp * lt);
    const double cosine = denom > 0 ? std::clamp(dot / denom, -1.0, 1.0) : -1.0;
    angles.push_back(std::acos(cosine) * kDegrees);
  }
}

void AngleSums::add(double angle_deg) {
  ++pixels;
  sum += angle_deg;
  sum_sq += angle_deg * angle_deg;
  under20 += angle_deg < 20.0;
  under25 += angle_deg < 25.0;
  under30 += angle_deg < 30.0;
}

void AngleSums::add(const AngleSums& other) {
  pixels += other.pixels;
  sum += other.sum;
  sum_sq += other.sum_sq;
  under20 += other.under20;
  under25 += other.under25;
  under30 += other.under30;
}

AngularSummary AngleSums::summary() const {
  AngularSummary s;
  s.pixels = pixels;
  if (pixels == 0) return s;
  const double n = static_cast<double>(pixels);
  s.mean = sum / n;
  s.std = std::sqrt(std::max(0.0, sum_sq / n - s.mean * s.mean));
  s.under20 = static_cast<double>(under20) * (100.0 / n);
  s.under25 = static_cast<double>(under25) * (100.0 / n);
  s.under30 = static_cast<double>(under30) * (100.0 / n);
  return s;
}

AngularSummary summarize_angles(const std::vector<double>& angles) {
  AngleSums sums;
  for (double a : angles) sums.add(a);
  return sums.summary();
}

double masked_mse(const float* a, const float* b, const float* mask, int channels, int64_t plane) {
  double error = 0, count = 0;
  for (int64_t i = 0; i < plane; ++i) {
    if (mask[i] <= 0.5f) continue;
    count += 1;
    for (int c = 0; c < channels; ++c) {
      const double d = double(a[c * plane + i]) - b[c * plane + i];
      error += d * d;
    }
  }
  return count > 0 ? error / (count * channels) : 0.0;
}

double masked_psnr(const float* a, const float* b, const float* mask, int width, int height) {
  const double mse = masked_mse(a, b, mask, 3, static_cast<int64_t>(width) * height);
  return mse > 0 ? 10.0 * std::log10(1.0 / mse) : std::numeric_limits<double>::infinity();
}

double masked_ssim(const float* a, const float* b, const float* mask, int width, int height) {
  const int r = 3;  // 7x7 window
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  const int64_t plane = static_cast<int64_t>(width) * height;
  double total = 0;
  int64_t count = 0;
  for (int y = r; y + r < height; ++y)
    for (int x = r; x + r < width; ++x) {
      if (mask[static_cast<int64_t>(y) * width + x] <= 0.5f) continue;
      for (int c = 0; c < 3; ++c) {
        double ma = 0, mb = 0, saa = 0, sbb = 0, sab = 0;
        for (int dy = -r; dy <= r; ++dy)
          for (int dx = -r; dx <= r; ++dx) {
            const int64_t i = c * plane + static_cast<int64_t>(y + dy) * width + (x + dx);
            ma += a[i];
            mb += b[i];
            saa += double(a[i]) * a[i];
            sbb += double(b[i]) * b[i];
            sab += double(a[i]) * b[i];
          }
        const double n = (2 * r + 1) * (2 * r + 1);
        ma /= n;
        mb /= n;
        const double va = saa / n - ma * ma, vb = sbb / n - mb * mb, cov = sab / n - ma * mb;
        total += ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
      }
      ++count;
    }
  return count > 0 ? total / (3.0 * count) : std::numeric_limits<double>::quiet_NaN();
}

double light_error(const float* a, const float* b) {
  const auto& gram = sh::illumination_gram_matrix();
  double total = 0;
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 9; ++i)
      for (int j = 0; j < 9; ++j)
        total += (double(a[c * 9 + i]) - b[c * 9 + i]) * gram[i][j] * (double(a[c * 9 + j]) - b[c * 9 + j]);
  return total / 3.0;
}

}  // namespace facetool
