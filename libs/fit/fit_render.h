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
  // The standard deviation of a Gaussian over the head that smooths the rendered normals, as a
  // fraction of the fitted face's outer-eye-corner distance in pixels (normal_smoothing.h;
  // docs/fit.md, "Smoothed normals"). 0: the mesh's own normals. Depth, masks and visibility are
  // the mesh's own either way.
  double normal_smoothing = 0.0;
};

struct FitRendering {
  int width = 0, height = 0;
  // Row-major, top row first. `head`: the fitted mesh covers the pixel (front faces); `mask`:
  // of those, the face region (the synthetic samples' mask).
  std::vector<uint8_t> head, mask;
  std::vector<float> normal;      // planar [3]: unit, camera frame (+X right, +Y up, +Z to the viewer); 0 off the head;
                                  // smoothed when settings.normal_smoothing > 0
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

// The distance in pixels between the fitted mesh's outer eye corners (landmarks 37 and 46 of the
// 68, fit.vertices[36] and [45]) as the fit's camera projects them: the scale of
// FitRenderSettings::normal_smoothing. `mesh` is fitted_mesh(model, fit).
double fitted_eye_distance_px(const FaceFit& fit, const FaceMesh& mesh);

// Renders the fit at fit.width x fit.height. `sampler` may be null when settings.visibility is
// false.
FitRendering render_fit(const FaceModel& model, const FaceFit& fit, const VisibilitySampler* sampler,
                        const FitRenderSettings& settings = {});

}  // namespace facetool
