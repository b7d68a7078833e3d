// Masked metrics for `facetool eval`: angles, PSNR, SSIM, light error.
#include "core/train/eval_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/sh/sh_gram.h"

namespace facetool {

void normal_angles_deg(const float* p, const float* t, const float* mask, int64_t plane,
                       std::vector<double>& angles) {
  const double kDegrees = 180.0 / 3.14159265358979323846;
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

AngularSummary summarize_angles(const std::vector<double>& angles) {
  AngularSummary s;
  s.pixels = static_cast<int64_t>(angles.size());
  if (angles.empty()) return s;
  double sum = 0, sq = 0;
  for (double a : angles) {
    sum += a;
    sq += a * a;
    s.under20 += a < 20.0;
    s.under25 += a < 25.0;
    s.under30 += a < 30.0;
  }
  const double n = static_cast<double>(angles.size());
  s.mean = sum / n;
  s.std = std::sqrt(std::max(0.0, sq / n - s.mean * s.mean));
  s.under20 *= 100.0 / n;
  s.under25 *= 100.0 / n;
  s.under30 *= 100.0 / n;
  return s;
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
