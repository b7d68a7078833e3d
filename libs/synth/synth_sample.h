// SynthSample: one generated training sample (planar float images plus its labels), and its
// EXR layout: channel names, metadata keys, reading and writing.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "libs/io/layered_image.h"
#include "libs/io/sample_files.h"
#include "core/sh/sh_types.h"
#include "libs/synth/pose_camera.h"

namespace facetool {

// Bumped whenever the content or layout of samples changes; stored in every file.
extern const char* const kSynthGeneratorVersion;

struct SynthSample {
  int width = 0, height = 0;
  // Planar [channels][height * width], rows top to bottom. Albedo, normal and depth cover the
  // whole head (0 off it); visibility is defined only inside the mask dilated by one pixel (0
  // outside it); the labels are meant for the mask (eroded for the losses).
  std::vector<float> image;       // 3: linear RGB, head rendered + background
  std::vector<float> albedo;      // 3: linear RGB in [0, 1]
  std::vector<float> normal;      // 3: unit XYZ, world = camera axes (+X right, +Y up, +Z to camera)
  std::vector<float> mask;        // 1: 1 in the face region, 0 elsewhere (erode for the losses)
  std::vector<float> visibility;  // 9: SH coefficients of the visibility
  std::vector<float> depth;       // 1: distance along -Z from the camera, 0 off the head
  sh::RgbLight light{};           // 27, channel-major R0..R8 G0..G8 B0..B8, final scale
  HeadPose pose;
  double fov_deg = 0;
  uint64_t run_seed = 0;          // --seed of the run
  int64_t index = 0;              // sample number within the run
  uint64_t sample_seed = 0;       // derive_seed(run_seed, index)
  std::string light_source;       // file the light came from
  std::string shape;              // "identity[...] expressions[name=weight ...]" for people
  std::string settings;           // fingerprint of the generator settings (generator_settings.h)
  std::string framing;            // framing_text of the camera's framing; "" for v1's
  int photo_edges = 0;            // simulated photo edges crossing the crop (0, 1 or 2)
  // The albedo texture painted on the face: "<source> mirror 0|1 gain R G B"; "" for none.
  std::string albedo_texture;
  // The face model's 68 landmark vertices projected into the crop: x0 y0 x1 y1 ... in pixels
  // (centres at integers), as prepare-real's facetool:landmarks; empty for a fixed mesh.
  std::vector<double> landmarks;
  int64_t rays_cast = 0;          // visibility rays (not stored)
  // Where the time went, in thread CPU seconds (not stored): shape + pose + BVH + primary rays, visibility rays,
  // albedo + light + rendering + background.
  double seconds_geometry = 0, seconds_visibility = 0, seconds_shading = 0;

  size_t plane() const { return static_cast<size_t>(width) * height; }
};

// Channel names in the EXR: R G B, albedo.R/G/B, normal.X/Y/Z, mask, visibility.0..8, depth.Z;
// metadata keys start with "facetool:" (see docs/synthetic-data.md). Reading keeps only these
// (other channels, such as an input prior, are read by libs/data/training_sample.h).
LayeredImage synth_sample_to_image(const SynthSample& sample);
SynthSample synth_sample_from_image(const LayeredImage& image, const std::string& source);

void write_synth_sample(const std::string& path, const SynthSample& sample);
SynthSample read_synth_sample(const std::string& path);

// Only the metadata of a sample file (no pixels): for resuming and manifests. Throws
// facetool::Error when the file is unreadable or not a facetool sample.
struct SynthSampleInfo {
  std::string generator_version;
  uint64_t run_seed = 0, sample_seed = 0;
  int64_t index = 0;
  int width = 0, height = 0;
  HeadPose pose;
  double fov_deg = 0;
  std::string light_source;
  std::string settings;  // "" in samples written before settings were recorded
};
SynthSampleInfo read_synth_sample_info(const std::string& path);

}  // namespace facetool
