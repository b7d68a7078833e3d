// The parity harness's table: op cases that run on any backend and return named outputs.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/backend/backend.h"

namespace facetool::parity {

// The test geometry: batch and spatial size; each case picks its own channel counts.
struct Geometry {
  int64_t n, h, w;
  std::string label() const;  // "n3_5x13"
};

// Named results of one run, downloaded to the host.
using Outputs = std::vector<std::pair<std::string, std::vector<float>>>;

struct OpCase {
  std::string name;
  double atol;
  double rtol;
  // Builds seeded inputs on `backend`, runs the op forward and backward, returns every output;
  // nullopt when the geometry does not apply to this op.
  std::function<std::optional<Outputs>(Backend& backend, const Geometry& g)> run;
};

const std::vector<OpCase>& op_cases();
const std::vector<Geometry>& geometries();

}  // namespace facetool::parity
