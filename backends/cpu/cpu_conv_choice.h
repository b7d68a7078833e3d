// The cpu backend's measured choices per machine: the convolution algorithm per layer shape, the fused forward's batch chunk.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "backends/cpu/cpu_im2col.h"

namespace facetool::cpu {

enum class ConvAlgorithm { Im2col, Winograd, Dnnl, Direct };

std::string conv_algorithm_name(ConvAlgorithm algorithm);
std::optional<ConvAlgorithm> parse_conv_algorithm(const std::string& name);

// One layer shape as the choice sees it: the batch and the geometry.
std::string conv_shape_key(const ConvGeometry& g, int64_t batch, int64_t out_channels);

// The algorithms that can run this shape (Winograd: 3x3, stride 1, same size; oneDNN: always
// offered, it may still decline at run time; direct: stride 1, direct_conv_applicable).
std::vector<ConvAlgorithm> applicable_conv_algorithms(const ConvGeometry& g,
                                                      int64_t out_channels);

// The rule used when nothing was measured for a shape (from measurements on the machine kind
// of docs/performance.md): Winograd where winograd_applicable (3x3 same convolutions with >= 16
// channels on both sides); direct for a stride-1 kernel over 1x1 with at most
// kDirectMaxOutChannels outputs (its im2col matrix would be written to be read once: dlib's face
// detector's last layer, 45 channels under a 9x9 kernel into 1, 3.8 -> 0.8 ms); im2col + SGEMM
// otherwise. The plain path (training) follows the same rule without direct.
constexpr int64_t kDirectMaxOutChannels = 4;
ConvAlgorithm default_conv_algorithm(const ConvGeometry& g, int64_t out_channels);

// The algorithm for this shape, first of: set_conv_algorithm_override(); the environment's
// FACETOOL_CONV_ALGORITHM (im2col, winograd, dnnl, direct); this machine's measured choice from the
// cache file (written by `facetool bench conv --save`); default_conv_algorithm(). An algorithm
// that does not apply to the shape falls back to the default.
ConvAlgorithm chosen_conv_algorithm(const ConvGeometry& g, int64_t batch, int64_t out_channels);

// Forces one algorithm for every shape it applies to (tests, benchmarks); nullopt undoes it.
void set_conv_algorithm_override(std::optional<ConvAlgorithm> algorithm);

// The per-machine cache: FACETOOL_CONV_CACHE when set (empty: no cache), else
// $XDG_CACHE_HOME/facetool/conv-algorithms.txt or ~/.cache/facetool/conv-algorithms.txt.
// Lines are "<machine> <key> <value>": a shape key and its algorithm, or a fused chunk key and
// its image count; lines of other machines, and values that do not parse, are ignored. The
// machine is the CPU model and the thread count.
std::string conv_cache_path();
std::string conv_machine_name();
// `machine`'s lines of the file at `path` (key -> value; later lines win; no file: none).
std::map<std::string, std::string> read_machine_choices(const std::string& path, const std::string& machine);
// Records measured values (replacing this machine's earlier lines for the same keys, keeping
// every other line) and writes the file atomically; throws facetool::Error naming the file
// when it cannot. A running process keeps the choices it read at its first lookup.
void save_machine_choices(const std::vector<std::pair<std::string, std::string>>& choices);
// save_machine_choices for measured convolution winners.
void save_conv_choices(const std::vector<std::pair<std::string, ConvAlgorithm>>& choices);

// The fused forward runs a large batch a few images at a time so that activations can stay in
// cache from layer to layer (PaperNetwork::forward_fused). The rule when nothing was measured:
// as many images as fit their widest activation (`bytes_per_image`) in kFusedChunkBytes, at least
// one (measured on the reference machine of docs/performance.md; another CPU may prefer the
// whole batch: `facetool bench network --save` measures it).
constexpr int64_t kFusedChunkBytes = int64_t{4} << 20;
int64_t default_fused_chunk(int64_t bytes_per_image, int64_t batch);
// The images per chunk for a batch, first of: set_fused_chunk_override(); this machine's
// measured choice for this activation size (key "fused_chunk_<bytes>B", 0 meaning the whole
// batch); default_fused_chunk(). Always in [1, batch].
int64_t chosen_fused_chunk(int64_t bytes_per_image, int64_t batch);
// Forces the images per chunk (0: the whole batch) for every size (tests, benchmarks); nullopt
// undoes it.
void set_fused_chunk_override(std::optional<int64_t> images);
// The activation size of the latest chosen_fused_chunk() call (0: none yet): what `bench network
// --save` measures for.
int64_t last_fused_chunk_request();
// Records this machine's measured chunk (0: the whole batch) for an activation size.
void save_fused_chunk(int64_t bytes_per_image, int64_t images);

}  // namespace facetool::cpu
