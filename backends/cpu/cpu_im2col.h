// im2col / col2im on column blocks: the unfolding that turns a convolution into a GEMM.
#pragma once

#include <cstdint>

namespace facetool::cpu {

// Geometry of one image's convolution: input [channels, height, width], square kernel.
struct ConvGeometry {
  int64_t channels, height, width;
  int64_t kernel, stride, pad;
  int64_t out_height, out_width;
  int64_t rows() const { return channels * kernel * kernel; }  // GEMM K: (c, ky, kx)
  int64_t pixels() const { return out_height * out_width; }
};

// col[r, j] for rows r of channels [c0, c1) (r counted from c0 * kernel^2) and output pixels
// p0 + j, j < count: the input value under kernel tap (ky, kx) of channel c, or 0 in the padding.
void im2col_block(const ConvGeometry& g, const float* image, int64_t c0, int64_t c1, int64_t p0,
                  int64_t count, float* col);

// The adjoint: image[c, iy, ix] += col[r, j] for every tap that im2col_block reads from there.
void col2im_block_add(const ConvGeometry& g, const float* col, int64_t c0, int64_t c1, int64_t p0,
                      int64_t count, float* image);

}  // namespace facetool::cpu
