// Per-band division (and the equivalent least-squares system) turning shading into illumination.
#include "core/sh/illumination_from_shading.h"

#include <cmath>
#include <utility>

#include "core/sh/clamped_cosine.h"
#include "core/sh/sh_basis.h"
#include "core/util/error.h"

namespace facetool::sh {

ShCoeffs illumination_from_shading(const ShCoeffs& shading) {
  ShCoeffs l{};
  for (int i = 0; i < kCoeffCount; ++i) l[i] = shading[i] / cosine_band_factor(sh_band(i));
  return l;
}

ShCoeffs shading_from_illumination(const ShCoeffs& light) {
  ShCoeffs s{};
  for (int i = 0; i < kCoeffCount; ++i) s[i] = light[i] * cosine_band_factor(sh_band(i));
  return s;
}

RgbLight illumination_from_shading(const RgbLight& shading) {
  RgbLight out{};
  for (int c = 0; c < 3; ++c)
    set_light_channel(out, c, illumination_from_shading(light_channel(shading, c)));
  return out;
}

RgbLight shading_from_illumination(const RgbLight& light) {
  RgbLight out{};
  for (int c = 0; c < 3; ++c)
    set_light_channel(out, c, shading_from_illumination(light_channel(light, c)));
  return out;
}

ShCoeffs illumination_from_shading_least_squares(const ShCoeffs& shading,
                                                 const std::vector<Vec3>& directions) {
  check(directions.size() >= static_cast<size_t>(kCoeffCount),
        "illumination from shading: need at least 9 directions, got ", directions.size());
  // Normal equations (A^T A) L = A^T b with A_si = c_i(n_s), b_s = sum_i S_i Y_i(n_s).
  double ata[kCoeffCount][kCoeffCount + 1] = {};
  for (const Vec3& n : directions) {
    const ShCoeffs y = sh_basis(n);
    ShCoeffs a{};
    double b = 0.0;
    for (int i = 0; i < kCoeffCount; ++i) {
      a[i] = cosine_band_factor(sh_band(i)) * y[i];
      b += shading[i] * y[i];
    }
    for (int i = 0; i < kCoeffCount; ++i) {
      for (int j = 0; j < kCoeffCount; ++j) ata[i][j] += a[i] * a[j];
      ata[i][kCoeffCount] += a[i] * b;
    }
  }
  // Gaussian elimination with partial pivoting on the augmented 9x10 system.
  for (int col = 0; col < kCoeffCount; ++col) {
    int pivot = col;
    for (int r = col + 1; r < kCoeffCount; ++r)
      if (std::fabs(ata[r][col]) > std::fabs(ata[pivot][col])) pivot = r;
    check(std::fabs(ata[pivot][col]) > 1e-12,
          "illumination from shading: the directions do not determine all 9 coefficients; "
          "use more, well spread directions");
    for (int j = 0; j <= kCoeffCount; ++j) std::swap(ata[col][j], ata[pivot][j]);
    for (int r = 0; r < kCoeffCount; ++r) {
      if (r == col) continue;
      const double f = ata[r][col] / ata[col][col];
      for (int j = col; j <= kCoeffCount; ++j) ata[r][j] -= f * ata[col][j];
    }
  }
  ShCoeffs l{};
  for (int i = 0; i < kCoeffCount; ++i) l[i] = ata[i][kCoeffCount] / ata[i][i];
  return l;
}

}  // namespace facetool::sh
