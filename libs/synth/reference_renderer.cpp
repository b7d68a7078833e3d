// ComponentRenderer on the SH library's triple product table (no backend, no plugin needed).
#include <cmath>

#include "core/sh/clamped_cosine.h"
#include "core/sh/triple_product.h"
#include "libs/synth/component_renderer.h"
#include "core/util/math_constants.h"

namespace facetool {
namespace {

class ReferenceRenderer : public ComponentRenderer {
 public:
  std::string name() const override { return "sh-triple-product (core/sh)"; }

  void render(int pixels, const float* albedo, const float* normal, const float* visibility,
              const sh::RgbLight& light, float* image) const override {
    const auto& entries = sh::TripleProductTable::get().all_entries();
    const double inv_pi = 1.0 / kPi;
    for (int p = 0; p < pixels; ++p) {
      const sh::Vec3 n{normal[p], normal[pixels + p], normal[2 * pixels + p]};
      const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (!(length > 0.0)) {
        for (int c = 0; c < 3; ++c) image[c * pixels + p] = 0.0f;
        continue;
      }
      const sh::ShCoeffs cosine = sh::clamped_cosine_coeffs(n);
      // e_i = sum_jk v_j c_k T_ijk: the transfer function's coefficients.
      double transfer[sh::kCoeffCount] = {};
      for (const sh::TripleEntry& t : entries)
        transfer[t.i] += t.value * visibility[t.j * pixels + p] * cosine[t.k];
      for (int c = 0; c < 3; ++c) {
        double radiance = 0.0;
        for (int i = 0; i < sh::kCoeffCount; ++i)
          radiance += light[c * sh::kCoeffCount + i] * transfer[i];
        image[c * pixels + p] = static_cast<float>(albedo[c * pixels + p] * inv_pi * radiance);
      }
    }
  }
};

}  // namespace

std::unique_ptr<ComponentRenderer> make_reference_renderer() {
  return std::make_unique<ReferenceRenderer>();
}

}  // namespace facetool
