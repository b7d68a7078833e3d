// Mirror averaging: a batch of crops run beside their left-right mirror images, the two answers averaged.
#pragma once

#include <vector>

namespace facetool {

// The network's four outputs for a batch, host copies, planar per image (NCHW).
struct NetworkAnswer {
  std::vector<float> albedo;      // [N,3,S,S]
  std::vector<float> normal;      // [N,3,S,S] world frame (+X the viewer's right)
  std::vector<float> visibility;  // [N,9,S,S] SH coefficients
  std::vector<float> light;       // [N,27] channel-major SH
};

// `images` [N,C,S,S] followed by the same N images mirrored left to right: [2N,C,S,S]. Channels
// from `normal_channel` on (when >= 0) hold a normal map (a network's input prior), whose x
// component changes sign in the mirror.
std::vector<float> with_mirror_images(const std::vector<float>& images, int count, int channels,
                                      int size, int normal_channel);

// The answer for 2N images (the first N, then their mirror images) made into N answers: each
// image's own answer averaged with its mirror image's answer seen back through the mirror (maps
// flipped left to right; the x component of normals and the SH coefficients odd in x, indices 3,
// 4 and 7, negated). Normals are normalised after averaging.
NetworkAnswer average_with_mirror(const NetworkAnswer& both, int count, int size);

}  // namespace facetool
