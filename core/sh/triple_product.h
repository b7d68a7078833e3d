// SH products: tripling coefficients T_ijk = integral of Y_i Y_j Y_k, and products of functions.
#pragma once

#include <vector>

#include "core/sh/sh_types.h"

namespace facetool::sh {

// One nonzero tripling coefficient.
struct TripleEntry {
  int i, j, k;
  double value;
};

// The 9x9x9 tripling coefficients of the basis in sh_basis.h, from closed forms (see the .cpp;
// verified against exact quadrature in tests/sh). Built once, then shared.
class TripleProductTable {
 public:
  static const TripleProductTable& get();

  double operator()(int i, int j, int k) const { return dense_[(i * kCoeffCount + j) * kCoeffCount + k]; }
  // The 25 distinct nonzero values with i <= j <= k.
  const std::vector<TripleEntry>& sorted_entries() const { return sorted_; }
  // All 83 nonzero (i, j, k) in every order, sorted by i, then j, then k.
  const std::vector<TripleEntry>& all_entries() const { return all_; }

 private:
  TripleProductTable();
  std::vector<double> dense_;
  std::vector<TripleEntry> sorted_;
  std::vector<TripleEntry> all_;
};

// Integral over the sphere of f g for SH-projected f and g: the dot product of coefficients.
double integrate_product(const ShCoeffs& f, const ShCoeffs& g);
// Coefficients e_i = sum_jk f_j g_k T_ijk of the product f g, projected back onto degree <= 2.
ShCoeffs product_coeffs(const ShCoeffs& f, const ShCoeffs& g);
// Integral over the sphere of h f g = sum_i h_i sum_jk f_j g_k T_ijk.
double integrate_triple(const ShCoeffs& h, const ShCoeffs& f, const ShCoeffs& g);

}  // namespace facetool::sh
