// The Gram matrix of the SH basis over the illumination-loss directions.
#include "core/sh/sh_gram.h"

#include <vector>

#include "core/sh/sh_basis.h"
#include "core/sh/sphere_samples.h"

namespace facetool::sh {

const std::array<std::array<double, 9>, 9>& illumination_gram_matrix() {
  static const std::array<std::array<double, 9>, 9> gram = [] {
    std::array<std::array<double, 9>, 9> g{};
    const std::vector<Vec3> dirs = fibonacci_sphere(kIlluminationSampleCount);
    for (const Vec3& w : dirs) {
      double y[9];
      sh_basis(w[0], w[1], w[2], y);
      for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 9; ++j) g[i][j] += y[i] * y[j];
    }
    for (auto& row : g)
      for (double& v : row) v /= static_cast<double>(dirs.size());
    return g;
  }();
  return gram;
}

}  // namespace facetool::sh
