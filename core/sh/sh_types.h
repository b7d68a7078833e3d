// Small value types of the SH library: directions, 9-coefficient functions, RGB lights, matrices.
#pragma once

#include <array>

namespace facetool::sh {

constexpr int kCoeffCount = 9;                  // real SH of degree l <= 2
constexpr int kLightCoeffCount = 3 * kCoeffCount;  // RGB, channel-major: R0..R8, G0..G8, B0..B8

using Vec3 = std::array<double, 3>;
using Mat3 = std::array<std::array<double, 3>, 3>;  // row-major, acts on column vectors
using ShCoeffs = std::array<double, kCoeffCount>;
using ShMatrix = std::array<std::array<double, kCoeffCount>, kCoeffCount>;  // [row][column]
using RgbLight = std::array<double, kLightCoeffCount>;

// The 9 coefficients of channel c (0 = R, 1 = G, 2 = B) of an RGB light, and back.
ShCoeffs light_channel(const RgbLight& light, int channel);
void set_light_channel(RgbLight& light, int channel, const ShCoeffs& coeffs);

}  // namespace facetool::sh
