// Gauss-Legendre x uniform-azimuth quadrature on the sphere, split at the equator of an axis.
#include "sphere_quadrature.h"
#include "core/util/math_constants.h"

#include <cmath>

namespace facetool::testing {

void gauss_legendre(int n, std::vector<double>& nodes, std::vector<double>& weights) {
  const double pi = kPi;
  nodes.assign(static_cast<size_t>(n), 0.0);
  weights.assign(static_cast<size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    double t = std::cos(pi * (i + 0.75) / (n + 0.5));
    double derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = t;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * t * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      derivative = n * (t * p1 - p0) / (t * t - 1.0);
      const double step = p1 / derivative;
      t -= step;
      if (std::fabs(step) < 1e-16) break;
    }
    double p0 = 1.0, p1 = t;
    for (int k = 2; k <= n; ++k) {
      const double p2 = ((2.0 * k - 1.0) * t * p1 - (k - 1.0) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    derivative = n * (t * p1 - p0) / (t * t - 1.0);
    nodes[static_cast<size_t>(i)] = t;
    weights[static_cast<size_t>(i)] = 2.0 / ((1.0 - t * t) * derivative * derivative);
  }
}

double integrate_sphere(const std::function<double(const sh::Vec3&)>& f, int n_t, int n_phi,
                        const sh::Vec3& axis) {
  const double pi = kPi;
  const double len = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  const sh::Vec3 a{axis[0] / len, axis[1] / len, axis[2] / len};
  // Orthonormal frame (e1, e2, a).
  sh::Vec3 helper = std::fabs(a[0]) < 0.9 ? sh::Vec3{1.0, 0.0, 0.0} : sh::Vec3{0.0, 1.0, 0.0};
  const double dot = helper[0] * a[0] + helper[1] * a[1] + helper[2] * a[2];
  sh::Vec3 e1{helper[0] - dot * a[0], helper[1] - dot * a[1], helper[2] - dot * a[2]};
  const double l1 = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
  for (double& v : e1) v /= l1;
  const sh::Vec3 e2{a[1] * e1[2] - a[2] * e1[1], a[2] * e1[0] - a[0] * e1[2],
                    a[0] * e1[1] - a[1] * e1[0]};
  std::vector<double> nodes, weights;
  gauss_legendre(n_t, nodes, weights);
  double total = 0.0;
  for (int half = 0; half < 2; ++half)
    for (size_t i = 0; i < nodes.size(); ++i) {
      const double t = 0.5 * nodes[i] + (half ? 0.5 : -0.5);  // map [-1, 1] onto the half
      const double s = std::sqrt(std::fmax(0.0, 1.0 - t * t));
      double ring = 0.0;
      for (int k = 0; k < n_phi; ++k) {
        const double phi = 2.0 * pi * (k + 0.5) / n_phi;
        const double c = s * std::cos(phi), d = s * std::sin(phi);
        ring += f({c * e1[0] + d * e2[0] + t * a[0], c * e1[1] + d * e2[1] + t * a[1],
                   c * e1[2] + d * e2[2] + t * a[2]});
      }
      total += 0.5 * weights[i] * ring * 2.0 * pi / n_phi;
    }
  return total;
}

}  // namespace facetool::testing
