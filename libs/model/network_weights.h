// Network weights on disk: a network plugin's parameters and buffers as one safetensors file.
#pragma once

#include <string>

#include "libs/image/crop_framing.h"
#include "libs/model/safetensors.h"
#include "core/plugin/network_plugin.h"

namespace facetool {

// Metadata written with the weights (docs/model-format.md):
//   format = "facetool-network", format_version = "1", architecture = plugin name,
//   width, input_size, input = "linear_rgb" (linear RGB in [0, 1]; 8-bit sRGB files decoded)
//   or "linear_rgb+PRIOR" for a network with NetworkConfig::input_prior PRIOR,
//   and, when the model was trained at a framing other than v1's, framing = framing_text(...)
//   (libs/image/crop_framing.h; a file without it, such as the former facetool-v1, is at v1's framing).
constexpr const char* kWeightsFormat = "facetool-network";
constexpr int kWeightsFormatVersion = 1;

struct WeightsHeader {
  std::string architecture;
  NetworkConfig config;
  CropFraming framing;  // how its input crops are framed (v1 when the file does not say)
};

// Reads and checks the metadata of a weights file; fails naming the file and the bad field.
WeightsHeader read_weights_header(const SafeTensors& file, const std::string& path);

// Copies every parameter and buffer of `net` (already built with the file's configuration)
// from `file`. Fails, naming the tensor, when one is missing, has another shape or dtype, or when
// the file holds tensors the network does not have (a landmark normal head's is not the
// network's: libs/model/landmark_normals.h reads it).
void load_network_weights(NetworkPlugin& net, const SafeTensors& file, const std::string& path);

// Writes the network's parameters, buffers and configuration to `path` atomically; the framing
// is written only when it is not v1's (so v1 files stay as they were).
void save_network_weights(const NetworkPlugin& net, const std::string& architecture,
                          const std::string& path, const CropFraming& framing = CropFraming{});

}  // namespace facetool
