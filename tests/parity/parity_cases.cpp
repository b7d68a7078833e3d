// The parity table: every op of core/ops/ops.h, forward and backward, as seeded runs.
#include "tests/parity/parity_cases.h"

#include "core/ops/ops.h"
#include "tests/support/test_support.h"

namespace facetool::parity {
namespace {

// Tolerances (atol, rtol): exact element-wise arithmetic; transcendental functions; short sums
// (reductions, per-pixel norms, bilinear taps); GEMM-based and batch-statistics ops, whose
// accumulation order differs between backends over up to 196-term dot products.
constexpr double kExactAtol = 1e-6, kExactRtol = 1e-6;
constexpr double kMathAtol = 1e-6, kMathRtol = 1e-5;
constexpr double kSumAtol = 1e-5, kSumRtol = 1e-4;
constexpr double kGemmAtol = 1e-4, kGemmRtol = 1e-3;

Tensor rnd(Backend& be, const Shape& s, unsigned seed, float lo = -1.0f, float hi = 1.0f) {
  return testing::random_tensor(be, s, seed, lo, hi);
}

Shape nchw(const Geometry& g, int64_t c) { return Shape{g.n, c, g.h, g.w}; }

void put(Outputs& out, const std::string& name, const Tensor& t) {
  out.emplace_back(name, t.to_host());
}

using GradSpecs = std::vector<std::pair<std::string, Shape>>;
using BackwardFn = std::function<void(const std::vector<const Tensor*>& grads, bool accumulate)>;

// Runs `backward` twice: into gradients holding a sentinel (accumulate=false must overwrite
// it) and on top of seeded non-zero values with accumulate=true. Records both.
void gradients(Outputs& out, Backend& be, const GradSpecs& specs, const BackwardFn& backward) {
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<Tensor> grads;
    for (size_t i = 0; i < specs.size(); ++i)
      grads.push_back(pass == 0 ? Tensor::full(be, specs[i].second, 1234.5f)
                                : rnd(be, specs[i].second, 900 + static_cast<unsigned>(i)));
    std::vector<const Tensor*> pointers;
    for (const Tensor& t : grads) pointers.push_back(&t);
    backward(pointers, pass == 1);
    for (size_t i = 0; i < specs.size(); ++i)
      put(out, specs[i].first + (pass == 1 ? "+accumulate" : ""), grads[i]);
  }
}

// A tensor with some exact zeros, for ops whose derivative has a kink at 0.
Tensor with_zeros(Backend& be, const Shape& s, unsigned seed) {
  std::vector<float> v = testing::random_values(static_cast<size_t>(s.numel()), seed);
  for (size_t i = 0; i < v.size(); i += 7) v[i] = 0.0f;
  return Tensor::from_host(be, s, v);
}

std::vector<OpCase> element_wise_cases() {
  std::vector<OpCase> cases;
  cases.push_back({"fill", kExactAtol, kExactRtol, [](Backend& be, const Geometry& g) {
                     Outputs out;
                     Tensor t = Tensor::empty(be, nchw(g, 5));
                     ops::fill(t, 0.37f);
                     put(out, "t", t);
                     return std::optional<Outputs>(out);
                   }});
  cases.push_back({"copy", kExactAtol, kExactRtol, [](Backend& be, const Geometry& g) {
                     Outputs out;
                     Tensor x = rnd(be, nchw(g, 5), 1);
                     Tensor y = Tensor::empty(be, x.shape());
                     ops::copy(x, y);
                     put(out, "y", y);
                     put(out, "clone", x.clone());
                     return std::optional<Outputs>(out);
                   }});
  cases.push_back({"add", kExactAtol, kExactRtol, [](Backend& be, const Geometry& g) {
                     Outputs out;
                     Tensor a = rnd(be, nchw(g, 5), 1), b = rnd(be, nchw(g, 5), 2);
                     put(out, "y", ops::add(a, b));
                     Tensor dy = rnd(be, a.shape(), 3);
                     gradients(out, be, {{"da", a.shape()}, {"db", a.shape()}},
                               [&](const auto& d, bool acc) {
                                 ops::add_backward(dy, d[0], d[1], acc);
                               });
                     return std::optional<Outputs>(out);
                   }});
  cases.push_back({"mul", kExactAtol, kExactRtol, [](Backend& be, const Geometry& g) {
                     Outputs out;
                     Tensor a = rnd(be, nchw(g, 5), 1), b = rnd(be, nchw(g, 5), 2);
                     put(out, "y", ops::mul(a, b));
                     Tensor dy = rnd(be, a.shape(), 3);
                     gradients(out, be, {{"da", a.shape()}, {"db", a.shape()}},
                               [&](const auto& d, bool acc) {
                                 ops::mul_backward(a, b, dy, d[0], d[1], acc);
                               });
                     gradients(out, be, {{"db_only", a.shape()}}, [&](const auto& d, bool acc) {
                       ops::mul_backward(a, b, dy, nullptr, d[0], acc);
                     });
                     return std::optional<Outputs>(out);
                   }});
  cases.push_back({"scale", kExactAtol, kExactRtol, [](Backend& be, const Geometry& g) {
                     Outputs out;
                     Tensor x = rnd(be, nchw(g, 5), 1);
                     put(out, "y", ops::scale(x, -1.7f));
                     Tensor dy = rnd(be, x.shape(), 3);
                     gradients(out, be, {{"dx", x.shape()}}, [&](const auto& d, bool acc) {
                       ops::scale_backward(dy, -1.7f, *d[0], acc);
                     });
                     return std::optional<Outputs>(out);
                   }});
  cases.push_back({"axpy", kExactAtol, kExactRtol, [](Backend& be, const Geometry& g) {
                     Outputs out;
                     Tensor x = rnd(be, nchw(g, 5), 1), y = rnd(be, nchw(g, 5), 2);
                     ops::axpy(0.3f, x, y);
                     put(out, "y", y);
                     return std::optional<Outputs>(out);
                   }});
  cases.push_back({"leaky_relu", kExactAtol, kExactRtol, [](Backend& be, const Geometry& g) {
                     Outputs out;
                     Tensor x = with_zeros(be, nchw(g, 5), 1);
                     put(out, "y", ops::leaky_relu(x, 0.2f));
                     Tensor dy = rnd(be, x.shape(), 3);
                     gradients(out, be, {{"dx", x.shape()}}, [&](const auto& d, bool acc) {
                       ops::leaky_relu_backward(x, 0.2f, dy, *d[0], acc);
                     });
                     return std::optional<Outputs>(out);
                   }});
  cases.push_back({"sigmoid", kMathAtol, kMathRtol, [](Backend& be, const Geometry& g) {
                     Outputs out;
                     Tensor x = rnd(be, nchw(g, 5), 1, -8.0f, 8.0f);
                     Tensor y = ops::sigmoid(x);
                     put(out, "y", y);
                     Tensor dy = rnd(be, x.shape(), 3);
                     gradients(out, be, {{"dx", x.shape()}}, [&](const auto& d, bool acc) {
                       ops::sigmoid_backward(y, dy, *d[0], acc);
                     });
                     return std::optional<Outputs>(out);
                   }});
  cases.push_back({"concat_channels", kExactAtol, kExactRtol, [](Backend& be, const Geometry& g) {
                     Outputs out;
                     Tensor a = rnd(be, nchw(g, 2), 1), b = rnd(be, nchw(g, 3), 2),
                            c = rnd(be, nchw(g, 1), 3);
                     Tensor y = ops::concat_channels({a, b, c});
                     put(out, "y", y);
                     Tensor dy = rnd(be, y.shape(), 4);
                     gradients(out, be, {{"da", a.shape()}, {"db", b.shape()}, {"dc", c.shape()}},
                               [&](const auto& d, bool acc) {
                                 ops::concat_channels_backward(dy, {d[0], d[1], d[2]}, acc);
                               });
                     return std::optional<Outputs>(out);
                   }});
  cases.push_back({"slice_channels", kExactAtol, kExactRtol, [](Backend& be, const Geometry& g) {
                     Outputs out;
                     Tensor x = rnd(be, nchw(g, 6), 1);
                     Tensor y = ops::slice_channels(x, 2, 3);
                     put(out, "y", y);
                     Tensor dy = rnd(be, y.shape(), 4);
                     gradients(out, be, {{"dx", x.shape()}}, [&](const auto& d, bool acc) {
                       ops::slice_channels_backward(dy, 2, *d[0], acc);
                     });
                     return std::optional<Outputs>(out);
                   }});
  return cases;
}

// Which gradients a convolution case asks for.
enum class ConvGrads { All, DxOnly, DwOnly };

// in -> out channels: the defaults take the im2col path; 3x3 stride-1 cases with >= 32 channels
// on both sides take the Winograd path of both backends.
OpCase conv_case(int k, int stride, bool bias, ConvGrads wanted, int64_t in_channels = 4,
                 int64_t out_channels = 6) {
  std::string name = "conv2d_k" + std::to_string(k) + "_s" + std::to_string(stride) +
                     (bias ? "_bias" : "_nobias");
  if (in_channels != 4 || out_channels != 6)
    name += "_" + std::to_string(in_channels) + "to" + std::to_string(out_channels);
  if (wanted == ConvGrads::DxOnly) name += "_dx_only";
  if (wanted == ConvGrads::DwOnly) name += "_dw_only";
  return {name, kGemmAtol, kGemmRtol, [=](Backend& be, const Geometry& g) {
            Outputs out;
            Tensor x = rnd(be, nchw(g, in_channels), 1);
            Tensor w = rnd(be, Shape{out_channels, in_channels, k, k}, 2, -0.5f, 0.5f);
            Tensor b = rnd(be, Shape{out_channels}, 3);
            Conv2dParams p;
            p.stride = stride;
            Tensor y = ops::conv2d(x, w, bias ? &b : nullptr, p);
            put(out, "y", y);
            Tensor dy = rnd(be, y.shape(), 4);
            GradSpecs specs;
            if (wanted != ConvGrads::DwOnly) specs.push_back({"dx", x.shape()});
            if (wanted != ConvGrads::DxOnly) specs.push_back({"dw", w.shape()});
            if (bias && wanted == ConvGrads::All) specs.push_back({"dbias", b.shape()});
            gradients(out, be, specs, [&](const auto& d, bool acc) {
              const Tensor* dx = wanted == ConvGrads::DwOnly ? nullptr : d[0];
              const Tensor* dw = wanted == ConvGrads::DxOnly ? nullptr
                                 : wanted == ConvGrads::DwOnly ? d[0]
                                                               : d[1];
              const Tensor* db = bias && wanted == ConvGrads::All ? d[2] : nullptr;
              ops::conv2d_backward(x, w, dy, dx, dw, db, p, acc);
            });
            return std::optional<Outputs>(out);
          }};
}

OpCase linear_case(bool bias) {
  return {bias ? "linear_bias" : "linear_nobias", kGemmAtol, kGemmRtol,
          [=](Backend& be, const Geometry& g) {
            Outputs out;
            const int64_t in = g.h * g.w;
            Tensor x = rnd(be, Shape{g.n, in}, 1);
            Tensor w = rnd(be, Shape{7, in}, 2);
            Tensor b = rnd(be, Shape{7}, 3);
            Tensor y = ops::linear(x, w, bias ? &b : nullptr);
            put(out, "y", y);
            Tensor dy = rnd(be, y.shape(), 4);
            GradSpecs specs = {{"dx", x.shape()}, {"dw", w.shape()}};
            if (bias) specs.push_back({"dbias", b.shape()});
            gradients(out, be, specs, [&](const auto& d, bool acc) {
              ops::linear_backward(x, w, dy, d[0], d[1], bias ? d[2] : nullptr, acc);
            });
            return std::optional<Outputs>(out);
          }};
}

OpCase batch_norm_case(bool training) {
  return {training ? "batch_norm_train" : "batch_norm_eval", kGemmAtol, kGemmRtol,
          [=](Backend& be, const Geometry& g) -> std::optional<Outputs> {
            if (training && g.n * g.h * g.w <= 1) return std::nullopt;
            Outputs out;
            Tensor x = rnd(be, nchw(g, 5), 1, -1.5f, 2.5f);
            Tensor gamma = rnd(be, Shape{5}, 2, 0.5f, 1.5f), beta = rnd(be, Shape{5}, 3);
            Tensor running_mean = rnd(be, Shape{5}, 5);
            Tensor running_var = rnd(be, Shape{5}, 6, 0.5f, 1.5f);
            BatchNormParams p;
            p.training = training;
            ops::BatchNormSaved saved;
            Tensor y = ops::batch_norm(x, gamma, beta, running_mean, running_var, p, &saved);
            put(out, "y", y);
            put(out, "running_mean", running_mean);
            put(out, "running_var", running_var);
            put(out, "save_mean", saved.mean);
            put(out, "save_invstd", saved.invstd);
            Tensor dy = rnd(be, x.shape(), 4);
            gradients(out, be, {{"dx", x.shape()}, {"dgamma", Shape{5}}, {"dbeta", Shape{5}}},
                      [&](const auto& d, bool acc) {
                        ops::batch_norm_backward(x, gamma, saved, dy, d[0], d[1], d[2], p, acc);
                      });
            gradients(out, be, {{"dx_only", x.shape()}}, [&](const auto& d, bool acc) {
              ops::batch_norm_backward(x, gamma, saved, dy, d[0], nullptr, nullptr, p, acc);
            });
            return out;
          }};
}

std::vector<OpCase> layer_cases() {
  std::vector<OpCase> cases;
  for (int k : {7, 3, 1})
    for (int stride : {1, 2})
      for (bool bias : {true, false}) cases.push_back(conv_case(k, stride, bias, ConvGrads::All));
  cases.push_back(conv_case(3, 1, false, ConvGrads::DxOnly));
  cases.push_back(conv_case(3, 2, true, ConvGrads::DwOnly));
  cases.push_back(conv_case(1, 1, false, ConvGrads::DwOnly));
  cases.push_back(conv_case(3, 1, true, ConvGrads::All, 32, 33));
  cases.push_back(linear_case(true));
  cases.push_back(linear_case(false));
  cases.push_back(batch_norm_case(true));
  cases.push_back(batch_norm_case(false));
  cases.push_back({"l2_normalize", kSumAtol, kSumRtol, [](Backend& be, const Geometry& g) {
                     Outputs out;
                     std::vector<float> v = testing::random_values(
                         static_cast<size_t>(g.n * 3 * g.h * g.w), 1);
                     const int64_t plane = g.h * g.w;
                     for (int c = 0; c < 3; ++c) v[c * plane] = 0.0f;  // pixel 0: norm < eps
                     Tensor x = Tensor::from_host(be, nchw(g, 3), v);
                     put(out, "y", ops::l2_normalize(x, 1e-6f));
                     Tensor dy = rnd(be, x.shape(), 3);
                     gradients(out, be, {{"dx", x.shape()}}, [&](const auto& d, bool acc) {
                       ops::l2_normalize_backward(x, 1e-6f, dy, *d[0], acc);
                     });
                     return std::optional<Outputs>(out);
                   }});
  return cases;
}

std::vector<OpCase> resample_and_loss_cases() {
  std::vector<OpCase> cases;
  cases.push_back({"upsample_bilinear2x", kSumAtol, kSumRtol, [](Backend& be, const Geometry& g) {
                     Outputs out;
                     Tensor x = rnd(be, nchw(g, 2), 1);
                     Tensor y = ops::upsample_bilinear2x(x);
                     put(out, "y", y);
                     Tensor dy = rnd(be, y.shape(), 3);
                     gradients(out, be, {{"dx", x.shape()}}, [&](const auto& d, bool acc) {
                       ops::upsample_bilinear2x_backward(dy, *d[0], acc);
                     });
                     return std::optional<Outputs>(out);
                   }});
  cases.push_back({"global_avg_pool", kSumAtol, kSumRtol, [](Backend& be, const Geometry& g) {
                     Outputs out;
                     Tensor x = rnd(be, nchw(g, 5), 1);
                     Tensor y = ops::global_avg_pool(x);
                     put(out, "y", y);
                     Tensor dy = rnd(be, y.shape(), 3);
                     gradients(out, be, {{"dx", x.shape()}}, [&](const auto& d, bool acc) {
                       ops::global_avg_pool_backward(dy, *d[0], acc);
                     });
                     return std::optional<Outputs>(out);
                   }});
  for (bool mean : {false, true})
    cases.push_back({mean ? "mean" : "sum", kSumAtol, kSumRtol,
                     [mean](Backend& be, const Geometry& g) {
                       Outputs out;
                       Tensor x = rnd(be, nchw(g, 5), 1);
                       put(out, "y", mean ? ops::mean(x) : ops::sum(x));
                       Tensor dy = Tensor::full(be, Shape{1}, -0.8f);
                       gradients(out, be, {{"dx", x.shape()}}, [&](const auto& d, bool acc) {
                         if (mean)
                           ops::mean_backward(dy, *d[0], acc);
                         else
                           ops::sum_backward(dy, *d[0], acc);
                       });
                       return std::optional<Outputs>(out);
                     }});
  for (bool empty_mask : {false, true})
    cases.push_back(
        {empty_mask ? "masked_mse_empty_mask" : "masked_mse", kSumAtol, kSumRtol,
         [empty_mask](Backend& be, const Geometry& g) {
           Outputs out;
           Tensor pred = rnd(be, nchw(g, 3), 1), target = rnd(be, nchw(g, 3), 2);
           std::vector<float> m = testing::random_values(static_cast<size_t>(g.n * g.h * g.w), 3,
                                                         -0.5f, 1.0f);
           for (float& v : m) v = empty_mask ? 0.0f : std::max(v, 0.0f);  // some zeros
           m[0] = empty_mask ? 0.0f : 1.0f;
           Tensor mask = Tensor::from_host(be, Shape{g.n, 1, g.h, g.w}, m);
           put(out, "loss", ops::masked_mse(pred, target, mask));
           Tensor dloss = Tensor::full(be, Shape{1}, 0.7f);
           gradients(out, be, {{"dpred", pred.shape()}, {"dtarget", pred.shape()}},
                     [&](const auto& d, bool acc) {
                       ops::masked_mse_backward(pred, target, mask, dloss, d[0], d[1], acc);
                     });
           gradients(out, be, {{"dtarget_only", pred.shape()}}, [&](const auto& d, bool acc) {
             ops::masked_mse_backward(pred, target, mask, dloss, nullptr, d[0], acc);
           });
           return std::optional<Outputs>(out);
         }});
  for (float weight_decay : {0.0f, 0.01f})
    cases.push_back({weight_decay > 0 ? "adam_step_weight_decay" : "adam_step", kMathAtol,
                     kMathRtol, [weight_decay](Backend& be, const Geometry& g) {
                       Outputs out;
                       Tensor param = rnd(be, nchw(g, 5), 1);
                       Tensor m = Tensor::zeros(be, param.shape());
                       Tensor v = Tensor::zeros(be, param.shape());
                       AdamParams p;
                       p.lr = 0.01f;
                       p.weight_decay = weight_decay;
                       for (int step = 1; step <= 3; ++step) {
                         Tensor grad = rnd(be, param.shape(), 10 + step);
                         p.step = step;
                         ops::adam_step(param, grad, m, v, p);
                       }
                       put(out, "param", param);
                       put(out, "m", m);
                       put(out, "v", v);
                       return std::optional<Outputs>(out);
                     }});
  return cases;
}

// A plugin-style kernel: y[i] = a * x[i] + b[i] + k over `count` items.
void affine_cpu(const CpuKernelArgs& args, int64_t begin, int64_t end) {
  const float* x = args.tensor(0);
  const float* b = args.tensor(1);
  float* y = args.tensor(2);
  for (int64_t i = begin; i < end; ++i)
    y[i] = args.float_arg(3) * x[i] + b[i] + static_cast<float>(args.int_arg(4));
}

const CustomKernel& affine_kernel() {
  static const CustomKernel kernel = [] {
    CustomKernel k;
    k.name = "parity_affine";
    k.opencl_source = R"CL(
__kernel void affine(__global const float* x, __global const float* b, __global float* y,
                     float a, int k, int count) {
  const int i = get_global_id(0);
  if (i < count) y[i] = a * x[i] + b[i] + (float)k;
}
)CL";
    k.cpu_entries["affine"] = &affine_cpu;
    return k;
  }();
  return kernel;
}

OpCase launch_case() {
  return {"launch_custom_kernel", kExactAtol, kExactRtol, [](Backend& be, const Geometry& g) {
            Outputs out;
            Tensor x = rnd(be, nchw(g, 5), 1), b = rnd(be, nchw(g, 5), 2);
            Tensor y = Tensor::zeros(be, x.shape());
            const int32_t count = static_cast<int32_t>(x.numel());
            ops::launch(affine_kernel(), "affine", x.numel(),
                        {KernelArg::of(x), KernelArg::of(b), KernelArg::of(y),
                         KernelArg::of(1.5f), KernelArg::of(int32_t{3}), KernelArg::of(count)});
            put(out, "y", y);
            return std::optional<Outputs>(out);
          }};
}

}  // namespace

std::string Geometry::label() const {
  return "n" + std::to_string(n) + "_" + std::to_string(h) + "x" + std::to_string(w);
}

const std::vector<OpCase>& op_cases() {
  static const std::vector<OpCase> cases = [] {
    std::vector<OpCase> all;
    for (auto group : {element_wise_cases(), layer_cases(), resample_and_loss_cases()})
      for (auto& c : group) all.push_back(c);
    all.push_back(launch_case());
    return all;
  }();
  return cases;
}

// Spatial sizes straddling work-group and tile sizes: H*W of 1, 3, 31, 33, 63, 65 (W of 1, 31,
// 11, 9, 65), at batch 1 and 3. Kept to twelve: ctest runs every test in its own process.
const std::vector<Geometry>& geometries() {
  static const std::vector<Geometry> all = [] {
    std::vector<Geometry> g;
    for (int64_t n : {1, 3})
      for (auto [h, w] : std::vector<std::pair<int64_t, int64_t>>{
               {1, 1}, {3, 1}, {1, 31}, {3, 11}, {7, 9}, {1, 65}})
        g.push_back({n, h, w});
    return g;
  }();
  return all;
}

}  // namespace facetool::parity
