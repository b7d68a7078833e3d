// OpenclBackend convolution (Winograd or im2col/col2im + CLBlast GEMM) and the fully connected layer.
#include <algorithm>

#include "backends/opencl/opencl_backend.h"
#include "backends/opencl/ops_winograd.h"

namespace facetool::opencl {
namespace {

const char* kConv = "conv_im2col.cl";

// The geometry of one convolution and how its batch is split into chunks of G images, each
// unrolled into one [Ci*K*K, G*Ho*Wo] column matrix so small images still give a wide GEMM.
struct ConvGeometry {
  int64_t batch, ci, h, w, co, k, stride, pad, ho, wo;
  int64_t rows() const { return ci * k * k; }
  int64_t plane_out() const { return ho * wo; }
  // A 1x1 stride-1 unpadded convolution reads x directly as its column matrix.
  bool pointwise() const { return k == 1 && stride == 1 && pad == 0; }
  bool winograd() const { return winograd_applicable(k, stride, pad, ci, co, ho == h && wo == w); }
  // The convolution as the Winograd path sees it: ci -> co on h x w.
  WinogradProblem winograd_problem() const { return {batch, ci, co, h, w}; }
  int64_t chunk;

  ConvGeometry(const Tensor& x, const Tensor& w, const Conv2dParams& p) {
    const Shape& xs = x.shape();
    batch = xs.n();
    ci = xs.c();
    h = xs.h();
    this->w = xs.w();
    co = w.shape().n();
    k = w.shape().h();
    stride = p.stride;
    pad = p.effective_pad(k);
    ho = (h + 2 * pad - k) / stride + 1;
    wo = (this->w + 2 * pad - k) / stride + 1;
    // GEMMs at least 4096 columns wide, within a 64 Mi-float (256 MiB) column buffer. (With
    // CLBlast called in column-major order, 4,096 to 16,384 columns ran alike on PoCL; the
    // smallest chunk needs the least memory and writes y directly when one image suffices.)
    const int64_t wanted_columns = 4096;
    const int64_t max_col_floats = int64_t(64) << 20;
    chunk = std::clamp<int64_t>((wanted_columns + plane_out() - 1) / plane_out(), 1, batch);
    chunk = std::max<int64_t>(1, std::min(chunk, max_col_floats / std::max<int64_t>(
                                                                      1, rows() * plane_out())));
  }
};

void im2col(OpenclBackend& be, const Tensor& x, const Tensor& col, const ConvGeometry& g,
            int64_t n0, int64_t count) {
  run_nd(be, kConv, "im2col", {g.wo, count * g.ho, g.rows()}, x, col, n0, count, g.ci, g.h,
             g.w, g.k, g.stride, g.pad, g.ho, g.wo);
}

// colT [count*Ho*Wo, Ci*K*K]: the transpose of im2col's matrix, for the weight gradient.
void im2col_transposed(OpenclBackend& be, const Tensor& x, const Tensor& col_t,
                       const ConvGeometry& g, int64_t n0, int64_t count) {
  run_nd(be, kConv, "im2col_transposed", {g.rows(), count * g.plane_out()}, x, col_t, n0, count,
         g.ci, g.h, g.w, g.k, g.stride, g.pad, g.ho, g.wo);
}

}  // namespace

void OpenclBackend::conv2d(const Tensor& x, const Tensor& w, const Tensor* bias, const Tensor& y,
                           const Conv2dParams& p) {
  const ConvGeometry g(x, w, p);
  if (g.winograd()) {
    winograd_convolve(*this, g.winograd_problem(), x, w, false, bias, y, false);
    return;
  }
  const int64_t plane = g.plane_out();
  const bool direct_output = g.chunk == 1;
  Tensor col = g.pointwise() && direct_output ? Tensor() : scratch(g.rows() * g.chunk * plane);
  Tensor packed = direct_output ? Tensor() : scratch(g.co * g.chunk * plane);
  for (int64_t n0 = 0; n0 < g.batch; n0 += g.chunk) {
    const int64_t count = std::min(g.chunk, g.batch - n0);
    const int64_t cols = count * plane;
    cl_mem b = nullptr;
    size_t b_offset = 0;
    if (col.defined()) {
      im2col(*this, x, col, g, n0, count);
      b = device_memory(col);
    } else {
      b = device_memory(x);
      b_offset = static_cast<size_t>(n0 * g.ci * g.h * g.w);
    }
    if (direct_output) {
      gemm_->run(false, false, g.co, cols, g.rows(), 1.0f, device_memory(w), 0, g.rows(), b,
                 b_offset, cols, 0.0f, device_memory(y), n0 * g.co * plane, cols);
    } else {
      gemm_->run(false, false, g.co, cols, g.rows(), 1.0f, device_memory(w), 0, g.rows(), b,
                 b_offset, cols, 0.0f, device_memory(packed), 0, cols);
      run_nd(*this, kConv, "unpack_batch", {plane, count * g.co}, packed, y,
                 bias ? device_memory(*bias) : device_memory(packed), bias != nullptr, n0, count,
                 g.co, plane);
    }
  }
  if (direct_output && bias)
    run_nd(*this, kConv, "add_channel_bias", {plane, g.batch * g.co}, y, *bias, g.co, plane);
}

void OpenclBackend::conv2d_backward(const Tensor& x, const Tensor& w, const Tensor& dy,
                                    const Tensor* dx, const Tensor* dw, const Tensor* dbias,
                                    const Conv2dParams& p, bool accumulate) {
  const ConvGeometry g(x, w, p);
  const int64_t plane = g.plane_out();
  const bool direct = g.chunk == 1;  // dy and x chunks are used in place
  if (dbias)
    run_groups(*this, kConv, "channel_sum", g.co, dy, *dbias, g.batch, g.co, plane, accumulate);
  if (!dx && !dw) return;
  if (g.winograd()) {
    // dx is the convolution of dy with the weights transposed and rotated by 180 degrees.
    if (dx)
      winograd_convolve(*this, {g.batch, g.co, g.ci, g.h, g.w}, dy, w, true, nullptr, *dx,
                        accumulate);
    if (dw) winograd_weight_gradient(*this, g.winograd_problem(), x, dy, *dw, accumulate);
    return;
  }

  Tensor packed_dy = direct ? Tensor() : scratch(g.co * g.chunk * plane);
  const bool col_from_x = g.pointwise() && direct;
  Tensor col = (dw && !col_from_x) ? scratch(g.rows() * g.chunk * plane) : Tensor();
  const bool dx_direct = g.pointwise() && direct;  // dcol is dx itself
  Tensor dcol = (dx && !dx_direct) ? scratch(g.rows() * g.chunk * plane) : Tensor();

  for (int64_t n0 = 0; n0 < g.batch; n0 += g.chunk) {
    const int64_t count = std::min(g.chunk, g.batch - n0);
    const int64_t cols = count * plane;
    cl_mem dy_mem = device_memory(dy);
    size_t dy_offset = static_cast<size_t>(n0 * g.co * plane);
    if (!direct) {
      run_nd(*this, kConv, "pack_batch", {plane, count * g.co}, dy, packed_dy, n0, count, g.co,
             plane);
      dy_mem = device_memory(packed_dy);
      dy_offset = 0;
    }
    if (dw) {
      const float beta = (n0 == 0 && !accumulate) ? 0.0f : 1.0f;
      if (col_from_x) {
        // dW[Co, rows] (+)= dY[Co, cols] * x[rows, cols]^T
        gemm_->run(false, true, g.co, g.rows(), cols, 1.0f, dy_mem, dy_offset, cols,
                   device_memory(x), static_cast<size_t>(n0 * g.ci * g.h * g.w), cols, beta,
                   device_memory(*dw), 0, g.rows());
      } else {
        // dW[Co, rows] (+)= dY[Co, cols] * colT[cols, rows]
        im2col_transposed(*this, x, col, g, n0, count);
        gemm_->run(false, false, g.co, g.rows(), cols, 1.0f, dy_mem, dy_offset, cols,
                   device_memory(col), 0, g.rows(), beta, device_memory(*dw), 0, g.rows());
      }
    }
    if (dx) {
      // dcol[rows, cols] = W[Co, rows]^T * dY[Co, cols]
      if (dx_direct) {
        gemm_->run(true, false, g.rows(), cols, g.co, 1.0f, device_memory(w), 0, g.rows(), dy_mem,
                   dy_offset, cols, accumulate ? 1.0f : 0.0f, device_memory(*dx),
                   n0 * g.ci * g.h * g.w, cols);
      } else {
        gemm_->run(true, false, g.rows(), cols, g.co, 1.0f, device_memory(w), 0, g.rows(), dy_mem,
                   dy_offset, cols, 0.0f, device_memory(dcol), 0, cols);
        run_nd(*this, kConv, "col2im", {g.w, count * g.h, g.ci}, dcol, *dx, n0, count, g.ci, g.h,
               g.w, g.k, g.stride, g.pad, g.ho, g.wo, accumulate);
      }
    }
  }
}

void OpenclBackend::linear(const Tensor& x, const Tensor& w, const Tensor* bias,
                           const Tensor& y) {
  const int64_t n = x.shape()[0], in = x.shape()[1], out = w.shape()[0];
  // y[N, out] = x[N, in] * w[out, in]^T
  gemm_->run(false, true, n, out, in, 1.0f, device_memory(x), 0, in, device_memory(w), 0, in,
             0.0f, device_memory(y), 0, out);
  if (bias) run_nd(*this, kConv, "add_channel_bias", {1, n * out}, y, *bias, out, 1);
}

void OpenclBackend::linear_backward(const Tensor& x, const Tensor& w, const Tensor& dy,
                                    const Tensor* dx, const Tensor* dw, const Tensor* dbias,
                                    bool accumulate) {
  const int64_t n = x.shape()[0], in = x.shape()[1], out = w.shape()[0];
  const float beta = accumulate ? 1.0f : 0.0f;
  // dx[N, in] (+)= dy[N, out] * w[out, in]
  if (dx)
    gemm_->run(false, false, n, in, out, 1.0f, device_memory(dy), 0, out, device_memory(w), 0, in,
               beta, device_memory(*dx), 0, in);
  // dw[out, in] (+)= dy[N, out]^T * x[N, in]
  if (dw)
    gemm_->run(true, false, out, in, n, 1.0f, device_memory(dy), 0, out, device_memory(x), 0, in,
               beta, device_memory(*dw), 0, in);
  if (dbias) run_groups(*this, kConv, "channel_sum", out, dy, *dbias, n, out, 1, accumulate);
}

}  // namespace facetool::opencl
