// Nested-loop convolution references in double (declared in conv_reference.h).
#include "tests/cpu/conv_reference.h"

namespace facetool::testing {
namespace {

// Calls visit(x index, w index, y index) for every product a convolution sums: each output
// pixel (n, co, oy, ox) with each tap (ci, ky, kx) that lands inside the input.
template <typename Visit>
void for_each_product(const Shape& xs, const Shape& ws, int stride, int64_t pad, int64_t ho,
                      int64_t wo, Visit visit) {
  for (int64_t n = 0; n < xs.n(); ++n)
    for (int64_t co = 0; co < ws.n(); ++co)
      for (int64_t oy = 0; oy < ho; ++oy)
        for (int64_t ox = 0; ox < wo; ++ox)
          for (int64_t ci = 0; ci < xs.c(); ++ci)
            for (int64_t ky = 0; ky < ws.h(); ++ky)
              for (int64_t kx = 0; kx < ws.w(); ++kx) {
                const int64_t iy = oy * stride - pad + ky, ix = ox * stride - pad + kx;
                if (iy < 0 || iy >= xs.h() || ix < 0 || ix >= xs.w()) continue;
                visit(((n * xs.c() + ci) * xs.h() + iy) * xs.w() + ix,
                      ((co * ws.c() + ci) * ws.h() + ky) * ws.w() + kx,
                      ((n * ws.n() + co) * ho + oy) * wo + ox);
              }
}

}  // namespace

std::vector<float> conv_reference(const std::vector<float>& x, const Shape& xs,
                                  const std::vector<float>& w, const Shape& ws,
                                  const std::vector<float>& b, int stride, int pad, int64_t ho,
                                  int64_t wo) {
  std::vector<double> y(static_cast<size_t>(xs.n() * ws.n() * ho * wo));
  for (size_t i = 0; i < y.size(); ++i) y[i] = b[(i / static_cast<size_t>(ho * wo)) % ws.n()];
  for_each_product(xs, ws, stride, pad, ho, wo, [&](int64_t xi, int64_t wi, int64_t yi) {
    y[yi] += double(x[xi]) * w[wi];
  });
  return std::vector<float>(y.begin(), y.end());
}

std::vector<float> conv_dx_reference(const std::vector<float>& dy, const Shape& xs,
                                     const std::vector<float>& w, const Shape& ws, int64_t pad,
                                     int64_t ho, int64_t wo) {
  std::vector<double> dx(static_cast<size_t>(xs.numel()), 0.0);
  for_each_product(xs, ws, 1, pad, ho, wo, [&](int64_t xi, int64_t wi, int64_t yi) {
    dx[xi] += double(dy[yi]) * w[wi];
  });
  return std::vector<float>(dx.begin(), dx.end());
}

std::vector<float> conv_dw_reference(const std::vector<float>& x, const Shape& xs,
                                     const std::vector<float>& dy, const Shape& ws, int64_t pad,
                                     int64_t ho, int64_t wo) {
  std::vector<double> dw(static_cast<size_t>(ws.numel()), 0.0);
  for_each_product(xs, ws, 1, pad, ho, wo, [&](int64_t xi, int64_t wi, int64_t yi) {
    dw[wi] += double(dy[yi]) * x[xi];
  });
  return std::vector<float>(dw.begin(), dw.end());
}

}  // namespace facetool::testing
