// Per-pixel transfer coefficients from the SH tripling table and the clamped cosine.
#include "core/sh/pixel_transfer.h"

#include "core/sh/clamped_cosine.h"
#include "core/sh/triple_product.h"

namespace facetool {

sh::ShCoeffs pixel_transfer(const sh::Vec3& n, const sh::ShCoeffs& v) {
  const sh::ShCoeffs cosine = sh::clamped_cosine_coeffs(n);
  sh::ShCoeffs t{};
  for (const sh::TripleEntry& e : sh::TripleProductTable::get().all_entries()) t[e.i] += e.value * v[e.j] * cosine[e.k];
  return t;
}

std::vector<double> transfer_coefficients(const std::vector<float>& normal, const std::vector<float>& visibility,
                                          const std::vector<uint8_t>& mask, size_t plane) {
  std::vector<double> t(9 * plane, 0.0);
  for (size_t p = 0; p < plane; ++p) {
    if (!mask[p]) continue;
    sh::ShCoeffs v;
    for (int j = 0; j < 9; ++j) v[j] = visibility[j * plane + p];
    const sh::ShCoeffs tp = pixel_transfer({normal[p], normal[plane + p], normal[2 * plane + p]}, v);
    for (int i = 0; i < 9; ++i) t[i * plane + p] = tp[i];
  }
  return t;
}

}  // namespace facetool
