// Backgrounds for the pixels outside the face: views of the light's environment map from the
// camera (they contain no faces), or random crops of images from a folder (--backgrounds).
#pragma once

#include <string>
#include <vector>

#include "libs/synth/light_source.h"
#include "libs/synth/pose_camera.h"
#include "libs/synth/random.h"

namespace facetool {

class BackgroundSource {
 public:
  // `image_folder` empty: environment views. Otherwise every image file in it (PNG, JPEG, EXR,
  // HDR, ...), sorted by name; throws facetool::Error when the folder has none.
  explicit BackgroundSource(const std::string& image_folder = "");

  bool uses_images() const { return !images_.empty(); }
  size_t image_count() const { return images_.size(); }
  const std::vector<std::string>& images() const { return images_; }

  // Fills planar RGB `rgb[3][w*h]` (linear, clamped to [0, 1]) for the camera. Environment
  // views show what the camera sees of the light: the panorama turned by `light.rotation`,
  // tinted by its gain and multiplied by `scale` (the factor applied to the SH light), or, for
  // SH-only sources, the SH light itself. Image backgrounds are read per call, cropped at a
  // random place and size (half to all of the shorter side) and resampled bilinearly.
  void fill(Random& random, const Camera& camera, const LightSource& source,
            const SampledLight& light, double scale, std::vector<float>& rgb) const;

 private:
  std::vector<std::string> images_;
};

}  // namespace facetool
