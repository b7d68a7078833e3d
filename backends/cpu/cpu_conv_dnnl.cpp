// Forward convolution by oneDNN's convolution primitive, one cached primitive per layer shape.
#include <dnnl.hpp>
#include <omp.h>

#include <map>
#include <memory>
#include <mutex>
#include <tuple>

#include "backends/cpu/cpu_conv.h"
#include "core/util/parallel_for.h"

namespace facetool::cpu {
namespace {

using dt = dnnl::memory::data_type;
using tag = dnnl::memory::format_tag;

// One layer shape's primitive with the layouts it chose and buffers for the reorders into and
// out of them, kept between calls. The mutex serialises calls that share it.
struct DnnlConv {
  std::mutex mutex;
  dnnl::convolution_forward primitive;
  dnnl::memory::desc user_src, user_weights, user_dst;
  dnnl::memory src, weights, dst;  // in the primitive's layouts (same as the user's when equal)
  bool reorder_src = false, reorder_weights = false, reorder_dst = false;
  dnnl::reorder to_src, to_weights, from_dst;  // created when the layouts differ
};

using Key = std::tuple<int64_t, int64_t, int64_t, int64_t, int64_t, int64_t, int64_t, int64_t>;

dnnl::engine& engine() {
  static dnnl::engine e(dnnl::engine::kind::cpu, 0);
  return e;
}

std::unique_ptr<DnnlConv> create(const ConvGeometry& g, int64_t batch, int64_t out_channels) {
  auto conv = std::make_unique<DnnlConv>();
  const dnnl::memory::dims src_dims{batch, g.channels, g.height, g.width};
  const dnnl::memory::dims weight_dims{out_channels, g.channels, g.kernel, g.kernel};
  const dnnl::memory::dims dst_dims{batch, out_channels, g.out_height, g.out_width};
  const dnnl::memory::dims strides{g.stride, g.stride};
  const dnnl::memory::dims pad_left{g.pad, g.pad};
  const dnnl::memory::dims pad_right{(g.out_height - 1) * g.stride + g.kernel - g.height - g.pad,
                                     (g.out_width - 1) * g.stride + g.kernel - g.width - g.pad};
  conv->user_src = dnnl::memory::desc(src_dims, dt::f32, tag::nchw);
  conv->user_weights = dnnl::memory::desc(weight_dims, dt::f32, tag::oihw);
  conv->user_dst = dnnl::memory::desc(dst_dims, dt::f32, tag::nchw);
  const dnnl::convolution_forward::desc desc(
      dnnl::prop_kind::forward_inference, dnnl::algorithm::convolution_direct,
      dnnl::memory::desc(src_dims, dt::f32, tag::any),
      dnnl::memory::desc(weight_dims, dt::f32, tag::any),
      dnnl::memory::desc(dst_dims, dt::f32, tag::any), strides, pad_left, pad_right);
  const dnnl::convolution_forward::primitive_desc pd(desc, engine());
  conv->primitive = dnnl::convolution_forward(pd);
  conv->reorder_src = pd.src_desc() != conv->user_src;
  conv->reorder_weights = pd.weights_desc() != conv->user_weights;
  conv->reorder_dst = pd.dst_desc() != conv->user_dst;
  auto reorder = [](const dnnl::memory::desc& from, const dnnl::memory::desc& to) {
    return dnnl::reorder(dnnl::reorder::primitive_desc(engine(), from, engine(), to));
  };
  if (conv->reorder_src) conv->to_src = reorder(conv->user_src, pd.src_desc());
  if (conv->reorder_weights) conv->to_weights = reorder(conv->user_weights, pd.weights_desc());
  if (conv->reorder_dst) conv->from_dst = reorder(pd.dst_desc(), conv->user_dst);
  if (conv->reorder_src) conv->src = dnnl::memory(pd.src_desc(), engine());
  if (conv->reorder_weights) conv->weights = dnnl::memory(pd.weights_desc(), engine());
  if (conv->reorder_dst) conv->dst = dnnl::memory(pd.dst_desc(), engine());
  if (!conv->reorder_src) conv->src = dnnl::memory(pd.src_desc(), engine(), nullptr);
  if (!conv->reorder_weights) conv->weights = dnnl::memory(pd.weights_desc(), engine(), nullptr);
  if (!conv->reorder_dst) conv->dst = dnnl::memory(pd.dst_desc(), engine(), nullptr);
  return conv;
}

// The cached primitive for this shape, created on first use; nullptr when oneDNN has none.
DnnlConv* lookup(const ConvGeometry& g, int64_t batch, int64_t out_channels) {
  static std::mutex mutex;
  static std::map<Key, std::unique_ptr<DnnlConv>> cache;
  const Key key{batch, g.channels, g.height, g.width, out_channels, g.kernel, g.stride, g.pad};
  std::lock_guard<std::mutex> lock(mutex);
  auto found = cache.find(key);
  if (found != cache.end()) return found->second.get();
  std::unique_ptr<DnnlConv> conv;
  try {
    conv = create(g, batch, out_channels);
  } catch (const dnnl::error&) {
    conv = nullptr;  // no implementation for this shape: remembered as such
  }
  return cache.emplace(key, std::move(conv)).first->second.get();
}

}  // namespace

bool dnnl_convolve(const ConvGeometry& g, int64_t batch, int64_t out_channels, const float* x,
                   const float* w, float* y, const Epilogue* epilogue) {
  DnnlConv* conv = lookup(g, batch, out_channels);
  if (!conv) return false;
  std::lock_guard<std::mutex> lock(conv->mutex);
  dnnl::stream stream(engine());
  dnnl::memory user_src(conv->user_src, engine(), const_cast<float*>(x));
  dnnl::memory user_weights(conv->user_weights, engine(), const_cast<float*>(w));
  dnnl::memory user_dst(conv->user_dst, engine(), y);
  if (!conv->reorder_src) conv->src.set_data_handle(const_cast<float*>(x));
  if (!conv->reorder_weights) conv->weights.set_data_handle(const_cast<float*>(w));
  if (!conv->reorder_dst) conv->dst.set_data_handle(y);
  // oneDNN's OpenMP team for this call: the pool's thread count (gemm_dnnl.cpp keeps it at one
  // for the sgemm calls made from inside parallel_for, so it is set back afterwards).
  omp_set_num_threads(parallel_thread_count());
  if (conv->reorder_src) conv->to_src.execute(stream, user_src, conv->src);
  if (conv->reorder_weights) conv->to_weights.execute(stream, user_weights, conv->weights);
  conv->primitive.execute(stream, {{DNNL_ARG_SRC, conv->src},
                                   {DNNL_ARG_WEIGHTS, conv->weights},
                                   {DNNL_ARG_DST, conv->dst}});
  if (conv->reorder_dst) conv->from_dst.execute(stream, conv->dst, user_dst);
  stream.wait();
  omp_set_num_threads(1);
  if (epilogue) {
    const int64_t planes = batch * out_channels;
    parallel_for(planes, 4, [&](int64_t begin, int64_t end) {
      for (int64_t plane = begin; plane < end; ++plane)
        epilogue->apply(y, plane / out_channels, plane % out_channels, 0, g.pixels());
    });
  }
  return true;
}

}  // namespace facetool::cpu
