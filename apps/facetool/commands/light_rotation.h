// Light angles given on the command line: "yaw,pitch,roll" rotations and "azimuth,elevation" directions, in degrees.
#pragma once

#include <array>
#include <string>

#include "core/sh/sh_types.h"

namespace facetool {

// "azimuth,elevation" in degrees -> the two angles (libs/light/direction_light.h); UsageError otherwise.
std::array<double, 2> parse_azimuth_elevation(const std::string& text);

// "yaw,pitch,roll" in degrees -> the three angles; UsageError otherwise.
std::array<double, 3> parse_rotation(const std::string& text);

// R = Ry(yaw) Rx(pitch) Rz(roll), each counter-clockwise about its axis looking down the axis
// towards the origin (right-hand rule), the order and sign `facetool synth` uses for head poses.
sh::Mat3 rotation_from_yaw_pitch_roll(const std::array<double, 3>& degrees);

}  // namespace facetool
