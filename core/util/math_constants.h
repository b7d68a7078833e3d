// Mathematical constants used across facetool, defined once.
#pragma once

namespace facetool {

inline constexpr double kPi = 3.14159265358979323846;

}  // namespace facetool
