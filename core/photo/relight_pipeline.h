// `facetool relight` on photos: decompose each face once, then per new light render and paste back.
#pragma once

#include <string>
#include <vector>

#include "core/photo/photo_pipeline.h"
#include "core/face/face_crops.h"
#include "core/face/paste_back.h"
#include "core/relight/relight_math.h"
#include "core/sh/sh_types.h"

namespace facetool {

// A photo taken apart once: its faces' crops, the network's results, where each face pastes back,
// and each face's estimated light in the photo's frame.
struct DecomposedPhoto {
  std::string path;
  RgbImage photo;  // linear RGB
  int crop_size = 0;
  std::vector<FaceCrop> crops;
  Decomposition decomposition;
  std::vector<PasteRegion> regions;
  std::vector<sh::RgbLight> photo_lights;  // per face, photo frame (docs/photos.md)
  std::vector<float> alpha;                // [w*h] face coverage
  std::vector<float> old_shading;          // [3][w*h] estimated shading, 1 outside the faces
};

// Reads, detects, aligns and decomposes; throws facetool::Error naming the photo when it cannot
// be read or holds no face.
DecomposedPhoto decompose_photo(const std::string& path, FaceDetector& detector, Decomposer& decomposer,
                                Backend& backend, int crop_size, const PhotoInferOptions& options);

// The part of decompose_photo after the network: paste regions, face coverage, the estimated
// shading at the photo's resolution and each face's light turned into the photo's frame.
// `decomposition` holds one face per crop (the tests give synthetic ones).
DecomposedPhoto assemble_decomposed_photo(const std::string& path, RgbImage photo, std::vector<FaceCrop> crops,
                                          const Decomposition& decomposition, double feather);

struct RelightSettings {
  relight::Mode mode = relight::Mode::Ratio;
  float ratio_epsilon = relight::kDefaultRatioEpsilon;
  bool visibility = true;  // false: open hemisphere (--no-visibility)
};

// One relit photo at the photo's resolution (linear RGB) and the new shading (1 outside faces).
struct RelitPhoto {
  RgbImage image;
  std::vector<float> new_shading;  // [3][w*h]
};

// Replaces every face's light by `light` (photo frame): one render of all faces and a paste-back,
// no network pass.
RelitPhoto relight_photo(const DecomposedPhoto& photo, const sh::RgbLight& light,
                         const RelightSettings& settings, RendererPlugin& renderer, Backend& backend);

// A planar shading layer shown over the photo (the photo where no face is), for sheets.
RgbImage shading_over_photo(const DecomposedPhoto& photo, const std::vector<float>& shading);

// Tiles scaled to `height` pixels and set side by side with a 2-pixel gap.
RgbImage side_by_side(const std::vector<RgbImage>& tiles, int height);

// The light's lit sphere: the left square of its preview (light_preview.h), size x size.
RgbImage light_sphere(const sh::RgbLight& light, int size);

// light_sphere() drawn into the image's top-right corner.
void draw_light_sphere(RgbImage& image, const sh::RgbLight& light, int size);

}  // namespace facetool
