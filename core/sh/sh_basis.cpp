// Evaluation of the 9 real spherical harmonics and of their polynomial gradients.
#include "core/sh/sh_basis.h"

namespace facetool::sh {

void sh_basis(double x, double y, double z, double out[kCoeffCount]) {
  using K = ShConstants;
  out[0] = K::k0;
  out[1] = K::k1 * y;
  out[2] = K::k1 * z;
  out[3] = K::k1 * x;
  out[4] = K::k2 * x * y;
  out[5] = K::k2 * y * z;
  out[6] = K::k20 * (3.0 * z * z - 1.0);
  out[7] = K::k2 * x * z;
  out[8] = K::k22 * (x * x - y * y);
}

ShCoeffs sh_basis(const Vec3& d) {
  ShCoeffs out{};
  sh_basis(d[0], d[1], d[2], out.data());
  return out;
}

void sh_basis_gradient(const Vec3& d, double out[kCoeffCount][3]) {
  using K = ShConstants;
  const double x = d[0], y = d[1], z = d[2];
  const double rows[kCoeffCount][3] = {
      {0.0, 0.0, 0.0},
      {0.0, K::k1, 0.0},
      {0.0, 0.0, K::k1},
      {K::k1, 0.0, 0.0},
      {K::k2 * y, K::k2 * x, 0.0},
      {0.0, K::k2 * z, K::k2 * y},
      {0.0, 0.0, 6.0 * K::k20 * z},
      {K::k2 * z, 0.0, K::k2 * x},
      {2.0 * K::k22 * x, -2.0 * K::k22 * y, 0.0},
  };
  for (int i = 0; i < kCoeffCount; ++i)
    for (int a = 0; a < 3; ++a) out[i][a] = rows[i][a];
}

}  // namespace facetool::sh
