// The fit's products in the photo's frame and at its resolution: normals, depth, the face mask
// the fitted mesh covers and per-pixel SH visibility (Embree, as the synthetic generator).
#pragma once

#include <cstdint>
#include <vector>

#include "libs/fit/landmark_fit.h"
#include "libs/synth/face_mesh.h"
#include "libs/synth/visibility.h"

namespace facetool {

struct FitRenderSettings {
  bool visibility = true;
  // Visibility rays start this fraction of the fitted face's size along the normal (the
  // synthetic generator's 2e-3 of its [-1, 1] frame).
  float ray_offset_fraction = 1e-3f;
};

struct FitRendering {
  int width = 0, height = 0;
  // Row-major, top row first. `head`: the fitted mesh covers the pixel (front faces); `mask`:
  // of those, the face region (the synthetic samples' mask).
  std::vector<uint8_t> head, mask;
  std::vector<float> normal;      // planar [3]: unit, camera frame (+X right, +Y up, +Z to the viewer); 0 off the head
  std::vector<float> depth;       // distance along -Z from the camera (orthographic: from the
                                  // plane through the model's origin), the fit's units; 0 off the head
  std::vector<float> visibility;  // planar [9]: inside the mask dilated by one pixel, 0 elsewhere
  // Per pixel, the point of the neutral face the pixel sees (synth's albedo coordinates,
  // libs/synth/albedo_texture.h); 0 off the head.
  std::vector<Vec3f> reference;
  FaceMesh mesh;                  // the fitted mesh in the camera frame
  double seconds_geometry = 0, seconds_visibility = 0;  // thread CPU time: mesh + BVH + primary rays; visibility rays
  int64_t rays_cast = 0;
};

// The fitted mesh (all kept parts) in the fit's camera frame.
FaceMesh fitted_mesh(const FaceModel& model, const FaceFit& fit);

// Renders the fit at fit.width x fit.height. `sampler` may be null when settings.visibility is
// false.
FitRendering render_fit(const FaceModel& model, const FaceFit& fit, const VisibilitySampler* sampler,
                        const FitRenderSettings& settings = {});

}  // namespace facetool
