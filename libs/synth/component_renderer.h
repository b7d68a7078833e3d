// ComponentRenderer: turns per-pixel albedo, normal and visibility plus one SH light into an
// image, I = albedo / pi * integral L v max(0, w.n) dw, evaluated like the network's rendering
// layer. The generator renders every image through one of these.
#pragma once

#include <memory>
#include <string>

#include "core/sh/sh_types.h"

namespace facetool {

class ComponentRenderer {
 public:
  virtual ~ComponentRenderer() = default;
  virtual std::string name() const = 0;
  // Planar inputs of `pixels` pixels: albedo[3][pixels], normal[3][pixels],
  // visibility[9][pixels]; writes image[3][pixels]. Must be safe to call from several threads.
  virtual void render(int pixels, const float* albedo, const float* normal,
                      const float* visibility, const sh::RgbLight& light, float* image) const = 0;
};

// The SH library's triple product (sh::TripleProductTable), in double precision:
// I_c = albedo_c / pi * sum_i L_ci sum_jk v_j c_k(n) T_ijk, with c(n) = clamped_cosine_coeffs.
std::unique_ptr<ComponentRenderer> make_reference_renderer();

}  // namespace facetool
