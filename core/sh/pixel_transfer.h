// Per-pixel transfer coefficients: a normal and a visibility function folded into the 9 numbers
// a light is dotted with (the triple product the renderer evaluates).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace facetool {

// transfer_i(p) = sum_jk T_ijk v_j(p) c_k(n(p)) for every pixel p with mask[p] != 0 (0 elsewhere),
// planar [9][plane]; `normal` planar [3][plane], `visibility` [9][plane]. The renderer's
// per-pixel coefficients: I_c = albedo_c / pi * sum_i L_ci transfer_i
// (libs/synth/component_renderer.h).
std::vector<double> transfer_coefficients(const std::vector<float>& normal, const std::vector<float>& visibility,
                                          const std::vector<uint8_t>& mask, size_t plane);

}  // namespace facetool
