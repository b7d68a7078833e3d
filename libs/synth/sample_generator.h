// SampleGenerator: everything needed to turn (run seed, sample index) into one SynthSample:
// shape, albedo, pose, camera, Embree G-buffer and visibility, light, rendered image, background.
#pragma once

#include <memory>
#include <vector>

#include "libs/synth/albedo.h"
#include "libs/synth/background.h"
#include "libs/synth/component_renderer.h"
#include "libs/synth/face_model.h"
#include "libs/synth/light_source.h"
#include "libs/synth/photo_edge.h"
#include "libs/synth/pose_camera.h"
#include "libs/synth/albedo_texture.h"
#include "libs/synth/synth_sample.h"
#include "libs/synth/visibility.h"

namespace facetool {

struct SynthSettings {
  CameraSampling camera;
  PoseSampling pose;
  ShapeSampling shape;
  LightSampling light;
  int direction_count = 872;  // visibility directions (paper)
  // Visibility rays start this far along the normal ([-1, 1] units, ~0.25 mm on a head): enough
  // that facets of the ICT mesh do not shadow their neighbours at grazing angles.
  float ray_offset = 2e-3f;
  // Visibility is cast only inside the mask dilated by one pixel (0 elsewhere). True casts it for
  // every head pixel, as before the face-region mask (for tests and comparisons; ~2x slower).
  bool visibility_on_whole_head = false;
  // Simulated photo edges (photo_edge.h): beyond them the image gets camera.framing's border fill
  // and the mask is cut, as alignment does for a real photo; needs the ring-mean border fill.
  PhotoEdgeSampling photo_edges;
  // Photo-textured albedo (albedo_texture.h; `synth --albedo-textures`): this fraction of the
  // samples paints one of these textures, drawn at random and mirrored half of the time, on the
  // face instead of the procedural skin, lips and brows; its colour is scaled channel by channel
  // to the procedural skin colour the sample drew (the textures' own brightness is not known:
  // light and albedo from one photo are only defined up to a scale). Where a texture's weight is
  // below 1 the procedural albedo of that colour shows through; the eyes stay procedural. Empty:
  // the paper's procedural albedo only.
  std::shared_ptr<const std::vector<AlbedoTexture>> albedo_textures;
  double albedo_texture_fraction = 1.0;
};

// Where faces come from: random ICT Face Model shapes, or one fixed mesh (--mesh).
struct FaceSource {
  std::shared_ptr<const FaceModel> model;
  std::shared_ptr<const FaceMesh> mesh;
};

class SampleGenerator {
 public:
  SampleGenerator(FaceSource faces, std::vector<LightSource> lights, BackgroundSource backgrounds,
                  std::shared_ptr<const ComponentRenderer> renderer, SynthSettings settings);

  // Sample `index` of the run with seed `run_seed`. Depends on nothing else (not on threads,
  // shards or other samples), and may be called from several threads at once.
  SynthSample generate(uint64_t run_seed, int64_t index) const;

  const SynthSettings& settings() const { return settings_; }
  const std::vector<LightSource>& lights() const { return lights_; }
  const ComponentRenderer& renderer() const { return *renderer_; }
  const FaceSource& faces() const { return faces_; }
  const BackgroundSource& backgrounds() const { return backgrounds_; }
  // describe_generator_settings(*this) (generator_settings.h) and its fingerprint, which every
  // generated sample carries so that a resumed run can tell whether it was made the same way.
  const std::string& settings_description() const { return settings_description_; }
  const std::string& settings_fingerprint() const { return settings_fingerprint_; }

 private:
  FaceSource faces_;
  std::vector<LightSource> lights_;
  BackgroundSource backgrounds_;
  std::shared_ptr<const ComponentRenderer> renderer_;
  SynthSettings settings_;
  AlbedoModel albedo_model_;
  VisibilitySampler visibility_;
  std::string settings_description_;
  std::string settings_fingerprint_;
};

}  // namespace facetool
