// Access to the per-channel coefficients of channel-major RGB lights.
#include "core/sh/sh_types.h"

namespace facetool::sh {

ShCoeffs light_channel(const RgbLight& light, int channel) {
  ShCoeffs c{};
  for (int i = 0; i < kCoeffCount; ++i) c[i] = light[channel * kCoeffCount + i];
  return c;
}

void set_light_channel(RgbLight& light, int channel, const ShCoeffs& coeffs) {
  for (int i = 0; i < kCoeffCount; ++i) light[channel * kCoeffCount + i] = coeffs[i];
}

}  // namespace facetool::sh
