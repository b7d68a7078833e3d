// Simulated photo edges: in some samples one edge (or a corner) of a "photo" crosses the crop, and
// beyond it the image is filled as alignment fills crops that reach beyond a real photo.
#pragma once

#include <vector>

#include "libs/synth/random.h"

namespace facetool {

struct PhotoEdgeSampling {
  double fraction = 0;  // of the samples that get an edge (0: none, v1)
};

// Up to two half-planes in crop units centred on the crop ((pixel centre + 0.5) / size - 0.5):
// a point q is inside the photo when nx q.x + ny q.y <= offset for every edge.
struct PhotoEdges {
  int count = 0;
  double nx[2] = {0, 0}, ny[2] = {0, 0}, offset[2] = {0, 0};
};

// With probability `fraction`: one edge (70 %) or a corner of two perpendicular edges (30 %).
// The edge's outward normal points at k x 90 degrees (k uniform in 0..3, as a photo's sides lie)
// turned by up to +-20 degrees (the alignment turns the photo by the face's roll); its distance
// from the crop's centre is uniform in [0.15, 0.5] crop widths, so it cuts into the face region
// at worst and just grazes the crop at best.
PhotoEdges sample_photo_edges(Random& random, const PhotoEdgeSampling& sampling);

// The fraction of each pixel of a width x height crop inside the photo, from 4 x 4 samples per
// pixel (what warp_to_crop counts for a real photo; libs/face/face_alignment.h).
std::vector<float> photo_edge_coverage(const PhotoEdges& edges, int width, int height);

}  // namespace facetool
