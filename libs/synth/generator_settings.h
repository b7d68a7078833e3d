// The settings a synth run's samples depend on, as readable text and a short fingerprint, so a
// resumed run never reuses samples made with other lights, faces, sizes or sampling settings.
#pragma once

#include <string>

namespace facetool {

class SampleGenerator;

// One line per setting: generator version, image size and field of view, visibility settings,
// pose/shape/light sampling ranges, the framing and simulated photo edges (when not v1's),
// renderer, the face source (ICT model or mesh, with a hash
// of its geometry), every light source (name and a hash of its SH coefficients) and the
// background images. Equal text <=> samples made the same way (for the same seed and index).
std::string describe_generator_settings(const SampleGenerator& generator);

// 16 hex digits: FNV-1a (64 bit) of `text`.
std::string settings_fingerprint(const std::string& text);

}  // namespace facetool
