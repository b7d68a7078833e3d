// Albedo textures: albedo images in the neutral face's frontal projection, unwrapped from photos
// (`facetool unwrap`) and painted on synthetic faces (`synth --albedo-textures`); docs/synthetic-data.md.
#pragma once

#include <string>
#include <vector>

#include "libs/synth/face_mesh.h"

namespace facetool {

// Where a texture lies: the square [left, left + span] x [top - span, top] of the neutral face's
// x, y plane (its reference positions, seen from the front), size x size texels, texel (0, 0) at
// the upper left. A reference point maps to texel coordinates (centres at integers) by
//   u = (x - left) / span * size - 0.5,  v = (top - y) / span * size - 0.5.
// Points of the head that one front view shows on top of each other (under the chin, behind the
// ears) share a texel; the face region seen from the front has none.
struct AlbedoTextureFrame {
  int size = 0;
  float left = 0, top = 0, span = 0;
  bool operator==(const AlbedoTextureFrame& o) const {
    return size == o.size && left == o.left && top == o.top && span == o.span;
  }
};

// The frame of `reference` (a neutral mesh): the bounding square of its face-region vertices
// (fit_vertices) grown by 10 % about its centre, at size x size texels.
AlbedoTextureFrame albedo_texture_frame(const FaceMesh& reference, int size);

struct AlbedoTexture {
  AlbedoTextureFrame frame;
  std::vector<float> rgb;     // planar [3][size * size], linear albedo
  std::vector<float> weight;  // [size * size], in [0, 1]: how much the photo saw of each texel
  std::string source;         // what it was unwrapped from (facetool:source)
};

// Texel coordinates (centres at integers) of a reference point; `mirror` reflects the point
// about the frame's vertical centre line first (the face's left-right symmetry plane).
void albedo_texel(const AlbedoTextureFrame& frame, Vec3f reference, bool mirror, float& u, float& v);

// Bilinear look-up at a reference point, edges clamped: the albedo and its weight.
void sample_albedo_texture(const AlbedoTexture& texture, Vec3f reference, bool mirror, Vec3f& rgb, float& weight);

// Mean albedo over the texels weighted by their weight (0 where the weights sum to 0).
Vec3f mean_albedo(const AlbedoTexture& texture);

// EXR with channels R G B A (A = weight) and attributes facetool:albedo_texture_frame
// ("size left top span") and facetool:source. read_albedo_texture throws facetool::Error naming
// `path` when a channel or the frame is missing or malformed.
void write_albedo_texture(const std::string& path, const AlbedoTexture& texture);
AlbedoTexture read_albedo_texture(const std::string& path);
// Every .exr of `folder` (sorted by name, not recursive), all in one frame. Throws
// facetool::Error naming the folder when it holds none, or a file whose frame differs, and
// OutOfMemory when they would not fit in the memory available.
std::vector<AlbedoTexture> read_albedo_textures(const std::string& folder);

}  // namespace facetool
