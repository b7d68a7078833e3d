// Weights in a convolution algorithm's own form (Winograd's G w G^T), kept between inference calls.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

namespace facetool::cpu {

// The `floats` values that `transform` computes from the `raw` weights at w, computed once and
// reused while the weights at w hold the same values: each call compares them with a copy kept
// beside the result (a few microseconds for a layer of the shipped network, against the
// transform's tens), so a weight changed in place (a training step, a reload) is transformed
// anew. Entries of the least recently used
// weights go beyond kWeightCacheBytes (raw copies and results together). Thread-safe; the result
// stays valid while the caller holds it.
constexpr size_t kWeightCacheBytes = size_t{64} << 20;
std::shared_ptr<const std::vector<float>> cached_weight_transform(
    const float* w, size_t raw, size_t floats,
    const std::function<void(const float* w, float* out)>& transform);

}  // namespace facetool::cpu
