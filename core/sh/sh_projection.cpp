// Uniform-weight projection of sampled spherical functions onto the degree <= 2 SH.
#include "core/sh/sh_projection.h"

#include "core/sh/sh_basis.h"
#include "core/util/error.h"

namespace facetool::sh {

ShCoeffs project_samples(const std::vector<Vec3>& dirs, const std::vector<double>& values) {
  check(!dirs.empty(), "SH projection: no sample directions given");
  check(dirs.size() == values.size(), "SH projection: ", dirs.size(), " directions but ",
        values.size(), " values; give one value per direction");
  ShCoeffs out{};
  double y[kCoeffCount];
  for (size_t s = 0; s < dirs.size(); ++s) {
    sh_basis(dirs[s][0], dirs[s][1], dirs[s][2], y);
    for (int i = 0; i < kCoeffCount; ++i) out[i] += values[s] * y[i];
  }
  const double weight = 4.0 * ShConstants::kPi / static_cast<double>(dirs.size());
  for (double& c : out) c *= weight;
  return out;
}

ShCoeffs project_function(const std::vector<Vec3>& dirs,
                          const std::function<double(const Vec3&)>& f) {
  std::vector<double> values(dirs.size());
  for (size_t s = 0; s < dirs.size(); ++s) values[s] = f(dirs[s]);
  return project_samples(dirs, values);
}

}  // namespace facetool::sh
