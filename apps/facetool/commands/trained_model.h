// Helpers of pseudo-label and eval: a trained network from a weights file, face inputs as planes.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "apps/facetool/commands/command.h"
#include "core/backend/backend.h"
#include "libs/io/layered_image.h"
#include "core/plugin/network_plugin.h"
#include "libs/inference/model_loading.h"

namespace facetool {

// Creates the weights' architecture, builds it with their configuration and loads them.
LoadedNetwork load_trained_network(CommandContext& context, Backend& backend,
                                   const std::string& weights_path);

// Throws facetool::Error when sample `path` (width x height) is not at the network's input size,
// saying how to make samples of its size and framing.
void check_sample_size(const std::string& path, int width, int height, const LoadedNetwork& net);

// One face input at the network's size: a sample EXR (synthetic or real, kept whole in `file`
// so its channels and attributes can be written back) or a plain crop (PNG/JPEG as sRGB,
// EXR/HDR as linear), resized, with a full mask (every pixel is face).
struct FaceInput {
  std::string path;
  bool sample = false;      // a facetool sample EXR (synthetic or real)
  LayeredImage file;        // the sample's content (sample only)
  std::vector<float> image; // [3][S*S] linear RGB
  std::vector<float> mask;  // [S*S]
  std::vector<float> landmarks;  // the sample's facetool:landmarks (68 (x, y), crop pixels); none for a plain crop
};
FaceInput load_face_input(const std::string& path, const LoadedNetwork& net);

}  // namespace facetool
