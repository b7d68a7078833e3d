// Evaluation of SH expansions: dot products of coefficients with the basis at a direction.
#include "core/sh/sh_eval.h"

#include "core/sh/sh_basis.h"

namespace facetool::sh {

double sh_eval(const ShCoeffs& f, const Vec3& d) {
  double y[kCoeffCount];
  sh_basis(d[0], d[1], d[2], y);
  double s = 0.0;
  for (int i = 0; i < kCoeffCount; ++i) s += f[i] * y[i];
  return s;
}

std::array<double, 3> light_eval(const RgbLight& light, const Vec3& d) {
  return {sh_eval(light_channel(light, 0), d), sh_eval(light_channel(light, 1), d),
          sh_eval(light_channel(light, 2), d)};
}

}  // namespace facetool::sh
