// Zonal coefficients of the clamped cosine and their rotation to a normal by the zonal formula.
#include "core/sh/clamped_cosine.h"

#include <cmath>

#include "core/sh/sh_basis.h"
#include "core/util/error.h"
#include "core/util/math_constants.h"

namespace facetool::sh {
namespace {
}

double clamped_cosine_zonal(int l) {
  switch (l) {
    case 0: return std::sqrt(kPi) / 2.0;
    case 1: return std::sqrt(kPi / 3.0);
    case 2: return std::sqrt(5.0 * kPi) / 8.0;
    default: fail("clamped_cosine_zonal: degree ", l, " is outside 0..2");
  }
}

ShCoeffs clamped_cosine_about_z() {
  ShCoeffs c{};
  c[sh_index(0, 0)] = clamped_cosine_zonal(0);
  c[sh_index(1, 0)] = clamped_cosine_zonal(1);
  c[sh_index(2, 0)] = clamped_cosine_zonal(2);
  return c;
}

double cosine_band_factor(int l) {
  return std::sqrt(4.0 * kPi / (2.0 * l + 1.0)) * clamped_cosine_zonal(l);
}

ShCoeffs clamped_cosine_coeffs(const Vec3& n) {
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  check(std::isfinite(len) && len > 0.0, "clamped cosine: the normal (", n[0], ", ", n[1], ", ",
        n[2], ") has no direction; give a finite, nonzero normal");
  ShCoeffs y = sh_basis(Vec3{n[0] / len, n[1] / len, n[2] / len});
  for (int k = 0; k < kCoeffCount; ++k) y[k] *= cosine_band_factor(sh_band(k));
  return y;
}

}  // namespace facetool::sh
