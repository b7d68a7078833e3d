// Per-pixel transfer coefficients: a normal and a visibility function folded into the 9 numbers
// a light is dotted with (the triple product the renderer evaluates).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/sh/sh_types.h"

namespace facetool {

// transfer_i = sum_jk T_ijk v_j c_k(n) at one pixel: `n` a unit normal (normalised here; zero or
// non-finite throws facetool::Error, as clamped_cosine_coeffs), `v` its 9 visibility coefficients.
sh::ShCoeffs pixel_transfer(const sh::Vec3& n, const sh::ShCoeffs& v);

// transfer_i(p) = sum_jk T_ijk v_j(p) c_k(n(p)) for every pixel p with mask[p] != 0 (0 elsewhere),
// planar [9][plane]; `normal` planar [3][plane], `visibility` [9][plane]. The renderer's
// per-pixel coefficients: I_c = albedo_c / pi * sum_i L_ci transfer_i
// (libs/synth/component_renderer.h).
std::vector<double> transfer_coefficients(const std::vector<float>& normal, const std::vector<float>& visibility,
                                          const std::vector<uint8_t>& mask, size_t plane);

}  // namespace facetool
