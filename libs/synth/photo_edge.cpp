// Drawing simulated photo edges and their coverage of the crop.
#include "libs/synth/photo_edge.h"

#include <cmath>

#include "core/util/math_constants.h"

namespace facetool {

PhotoEdges sample_photo_edges(Random& random, const PhotoEdgeSampling& sampling) {
  PhotoEdges edges;
  if (sampling.fraction <= 0 || !random.bernoulli(sampling.fraction)) return edges;
  edges.count = random.bernoulli(0.3) ? 2 : 1;
  const double side = static_cast<double>(random.index(4)) * 0.5 * kPi;
  const double turn = random.uniform(-20.0, 20.0) * kPi / 180.0;
  for (int e = 0; e < edges.count; ++e) {
    const double angle = side + turn + e * 0.5 * kPi;
    edges.nx[e] = std::cos(angle);
    edges.ny[e] = std::sin(angle);
    edges.offset[e] = random.uniform(0.15, 0.5);
  }
  return edges;
}

std::vector<float> photo_edge_coverage(const PhotoEdges& edges, int w, int h) {
  std::vector<float> coverage(static_cast<size_t>(w) * h, 1.0f);
  if (edges.count == 0) return coverage;
  constexpr int n = 4;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int inside = 0;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const double qx = (x + (i + 0.5) / n) / w - 0.5, qy = (y + (j + 0.5) / n) / h - 0.5;
          bool in = true;
          for (int e = 0; e < edges.count; ++e) in = in && edges.nx[e] * qx + edges.ny[e] * qy <= edges.offset[e];
          inside += in;
        }
      coverage[static_cast<size_t>(y) * w + x] = static_cast<float>(inside) / (n * n);
    }
  return coverage;
}

}  // namespace facetool
