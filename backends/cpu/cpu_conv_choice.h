// Which forward convolution algorithm the cpu backend's fused path runs for each layer shape.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "backends/cpu/cpu_im2col.h"

namespace facetool::cpu {

enum class ConvAlgorithm { Im2col, Winograd, Dnnl };

std::string conv_algorithm_name(ConvAlgorithm algorithm);
std::optional<ConvAlgorithm> parse_conv_algorithm(const std::string& name);

// One layer shape as the choice sees it: the batch and the geometry.
std::string conv_shape_key(const ConvGeometry& g, int64_t batch, int64_t out_channels);

// The algorithms that can run this shape (Winograd: 3x3, stride 1, same size; oneDNN: always
// offered, it may still decline at run time).
std::vector<ConvAlgorithm> applicable_conv_algorithms(const ConvGeometry& g,
                                                      int64_t out_channels);

// The rule used when nothing was measured for a shape (from measurements on the machine kind
// of docs/performance.md): Winograd where winograd_applicable (3x3 same convolutions with >= 16
// channels on both sides), im2col + SGEMM otherwise; the plain path follows the same rule.
ConvAlgorithm default_conv_algorithm(const ConvGeometry& g, int64_t out_channels);

// The algorithm for this shape, first of: set_conv_algorithm_override(); the environment's
// FACETOOL_CONV_ALGORITHM (im2col, winograd, dnnl); this machine's measured choice from the
// cache file (written by `facetool bench conv --save`); default_conv_algorithm(). An algorithm
// that does not apply to the shape falls back to the default.
ConvAlgorithm chosen_conv_algorithm(const ConvGeometry& g, int64_t batch, int64_t out_channels);

// Forces one algorithm for every shape it applies to (tests, benchmarks); nullopt undoes it.
void set_conv_algorithm_override(std::optional<ConvAlgorithm> algorithm);

// The per-machine cache: FACETOOL_CONV_CACHE when set (empty: no cache), else
// $XDG_CACHE_HOME/facetool/conv-algorithms.txt or ~/.cache/facetool/conv-algorithms.txt.
// Lines are "<machine> <shape key> <algorithm>"; lines of other machines or that do not parse
// are ignored. The machine is the CPU model and the thread count.
std::string conv_cache_path();
std::string conv_machine_name();
// Records measured winners (replacing this machine's earlier lines for the same shapes) and
// writes the file atomically; throws facetool::Error naming the file when it cannot.
void save_conv_choices(const std::vector<std::pair<std::string, ConvAlgorithm>>& choices);

}  // namespace facetool::cpu
