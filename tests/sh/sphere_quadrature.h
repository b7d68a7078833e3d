// Test reference: product Gauss-Legendre (in cos theta) x uniform-phi quadrature on the sphere.
#pragma once

#include <functional>
#include <vector>

#include "core/sh/sh_types.h"

namespace facetool::testing {

// Nodes and weights of the n-point Gauss-Legendre rule on [-1, 1] (Newton on P_n).
void gauss_legendre(int n, std::vector<double>& nodes, std::vector<double>& weights);

// Integral over the unit sphere of f, with the polar axis along the unit vector `axis`:
// n_t Gauss-Legendre nodes in t = w.axis on each of [-1, 0] and [0, 1], n_phi uniform azimuths.
// Exact (to rounding) for polynomials of degree < 2 n_t in t and < n_phi in the azimuth on each
// half, so also for max(0, w.axis) times such polynomials: the kink lies on the split.
double integrate_sphere(const std::function<double(const sh::Vec3&)>& f, int n_t = 16,
                        int n_phi = 32, const sh::Vec3& axis = {0.0, 0.0, 1.0});

}  // namespace facetool::testing
