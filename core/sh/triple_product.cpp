// Tripling coefficients of the degree <= 2 real SH (closed forms) and SH product integrals.
#include "core/sh/triple_product.h"
#include "core/util/math_constants.h"

#include <algorithm>
#include <cmath>

namespace facetool::sh {
namespace {


// Distinct nonzero T_ijk, i <= j <= k, 0-based. Derived by expanding the products of the
// polynomials in sh_basis.h and integrating monomials over the sphere
// (integral of x^2 = 4 pi / 3, of x^4 = 4 pi / 5, of x^2 y^2 = 4 pi / 15, of x^2 y^2 z^2 =
// 4 pi / 105, ...). The paper's table (appendix, 1-based) prints T_668 = sqrt(15/pi)/14: the
// correct index is T_568 (0-based (4, 5, 7)); T_668 is zero. All other printed values agree.
std::vector<TripleEntry> closed_forms() {
  const double a = 1.0 / (2.0 * std::sqrt(kPi));     // sqrt(1 / (4 pi))
  const double b = std::sqrt(3.0 / (20.0 * kPi));    // sqrt(3 / (20 pi))
  const double c = std::sqrt(1.0 / (20.0 * kPi));    // sqrt(1 / (20 pi))
  const double d = std::sqrt(1.0 / (5.0 * kPi));     // sqrt(1 / (5 pi))
  const double e = std::sqrt(5.0 / kPi) / 7.0;       // sqrt(5 / pi) / 7
  const double f = std::sqrt(5.0 / kPi) / 14.0;      // sqrt(5 / pi) / 14
  const double g = std::sqrt(15.0 / kPi) / 14.0;     // sqrt(15 / pi) / 14
  std::vector<TripleEntry> t;
  for (int i = 0; i < kCoeffCount; ++i) t.push_back({0, i, i, a});
  t.insert(t.end(), {
                        {1, 1, 6, -c}, {1, 1, 8, -b}, {1, 2, 5, b},  {1, 3, 4, b},
                        {2, 2, 6, d},  {2, 3, 7, b},  {3, 3, 6, -c}, {3, 3, 8, b},
                        {4, 4, 6, -e}, {4, 5, 7, g},  {5, 5, 6, f},  {5, 5, 8, -g},
                        {6, 6, 6, e},  {6, 7, 7, f},  {6, 8, 8, -e}, {7, 7, 8, g},
                    });
  return t;
}

}  // namespace

TripleProductTable::TripleProductTable() : dense_(kCoeffCount * kCoeffCount * kCoeffCount, 0.0) {
  sorted_ = closed_forms();
  for (const TripleEntry& s : sorted_) {
    int p[3] = {s.i, s.j, s.k};
    std::sort(p, p + 3);
    do {
      dense_[(p[0] * kCoeffCount + p[1]) * kCoeffCount + p[2]] = s.value;
    } while (std::next_permutation(p, p + 3));
  }
  for (int i = 0; i < kCoeffCount; ++i)
    for (int j = 0; j < kCoeffCount; ++j)
      for (int k = 0; k < kCoeffCount; ++k)
        if ((*this)(i, j, k) != 0.0) all_.push_back({i, j, k, (*this)(i, j, k)});
}

const TripleProductTable& TripleProductTable::get() {
  static const TripleProductTable table;
  return table;
}

double integrate_product(const ShCoeffs& f, const ShCoeffs& g) {
  double s = 0.0;
  for (int i = 0; i < kCoeffCount; ++i) s += f[i] * g[i];
  return s;
}

ShCoeffs product_coeffs(const ShCoeffs& f, const ShCoeffs& g) {
  ShCoeffs e{};
  for (const TripleEntry& t : TripleProductTable::get().all_entries())
    e[t.i] += t.value * f[t.j] * g[t.k];
  return e;
}

double integrate_triple(const ShCoeffs& h, const ShCoeffs& f, const ShCoeffs& g) {
  return integrate_product(h, product_coeffs(f, g));
}

}  // namespace facetool::sh
