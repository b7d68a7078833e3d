// Per-pixel transfer coefficients from the SH tripling table and the clamped cosine.
#include "core/sh/pixel_transfer.h"

#include "core/sh/clamped_cosine.h"
#include "core/sh/triple_product.h"

namespace facetool {

std::vector<double> transfer_coefficients(const std::vector<float>& normal, const std::vector<float>& visibility,
                                          const std::vector<uint8_t>& mask, size_t plane) {
  const auto& entries = sh::TripleProductTable::get().all_entries();
  std::vector<double> t(9 * plane, 0.0);
  for (size_t p = 0; p < plane; ++p) {
    if (!mask[p]) continue;
    const sh::Vec3 n{normal[p], normal[plane + p], normal[2 * plane + p]};
    const sh::ShCoeffs cosine = sh::clamped_cosine_coeffs(n);
    for (const sh::TripleEntry& e : entries) t[e.i * plane + p] += e.value * visibility[e.j * plane + p] * cosine[e.k];
  }
  return t;
}

}  // namespace facetool
