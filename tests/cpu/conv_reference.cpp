// Nested-loop convolution references in double (declared in conv_reference.h).
#include "tests/cpu/conv_reference.h"

namespace facetool::testing {

std::vector<float> conv_reference(const std::vector<float>& x, const Shape& xs,
                                  const std::vector<float>& w, const Shape& ws,
                                  const std::vector<float>& b, int stride, int pad, int64_t ho,
                                  int64_t wo) {
  std::vector<float> y(static_cast<size_t>(xs.n() * ws.n() * ho * wo));
  for (int64_t n = 0; n < xs.n(); ++n)
    for (int64_t co = 0; co < ws.n(); ++co)
      for (int64_t oy = 0; oy < ho; ++oy)
        for (int64_t ox = 0; ox < wo; ++ox) {
          double acc = b[co];
          for (int64_t ci = 0; ci < xs.c(); ++ci)
            for (int64_t ky = 0; ky < ws.h(); ++ky)
              for (int64_t kx = 0; kx < ws.w(); ++kx) {
                const int64_t iy = oy * stride - pad + ky, ix = ox * stride - pad + kx;
                if (iy < 0 || iy >= xs.h() || ix < 0 || ix >= xs.w()) continue;
                acc += double(x[((n * xs.c() + ci) * xs.h() + iy) * xs.w() + ix]) *
                       w[((co * ws.c() + ci) * ws.h() + ky) * ws.w() + kx];
              }
          y[((n * ws.n() + co) * ho + oy) * wo + ox] = float(acc);
        }
  return y;
}

std::vector<float> conv_dx_reference(const std::vector<float>& dy, const Shape& xs,
                                     const std::vector<float>& w, const Shape& ws, int64_t pad,
                                     int64_t ho, int64_t wo) {
  std::vector<double> dx(static_cast<size_t>(xs.numel()), 0.0);
  for (int64_t n = 0; n < xs.n(); ++n)
    for (int64_t co = 0; co < ws.n(); ++co)
      for (int64_t oy = 0; oy < ho; ++oy)
        for (int64_t ox = 0; ox < wo; ++ox) {
          const double g = dy[((n * ws.n() + co) * ho + oy) * wo + ox];
          for (int64_t ci = 0; ci < xs.c(); ++ci)
            for (int64_t ky = 0; ky < ws.h(); ++ky)
              for (int64_t kx = 0; kx < ws.w(); ++kx) {
                const int64_t iy = oy - pad + ky, ix = ox - pad + kx;
                if (iy < 0 || iy >= xs.h() || ix < 0 || ix >= xs.w()) continue;
                dx[((n * xs.c() + ci) * xs.h() + iy) * xs.w() + ix] +=
                    g * w[((co * ws.c() + ci) * ws.h() + ky) * ws.w() + kx];
              }
        }
  return std::vector<float>(dx.begin(), dx.end());
}

std::vector<float> conv_dw_reference(const std::vector<float>& x, const Shape& xs,
                                     const std::vector<float>& dy, const Shape& ws, int64_t pad,
                                     int64_t ho, int64_t wo) {
  std::vector<double> dw(static_cast<size_t>(ws.numel()), 0.0);
  for (int64_t n = 0; n < xs.n(); ++n)
    for (int64_t co = 0; co < ws.n(); ++co)
      for (int64_t oy = 0; oy < ho; ++oy)
        for (int64_t ox = 0; ox < wo; ++ox) {
          const double g = dy[((n * ws.n() + co) * ho + oy) * wo + ox];
          for (int64_t ci = 0; ci < xs.c(); ++ci)
            for (int64_t ky = 0; ky < ws.h(); ++ky)
              for (int64_t kx = 0; kx < ws.w(); ++kx) {
                const int64_t iy = oy - pad + ky, ix = ox - pad + kx;
                if (iy < 0 || iy >= xs.h() || ix < 0 || ix >= xs.w()) continue;
                dw[((co * ws.c() + ci) * ws.h() + ky) * ws.w() + kx] +=
                    g * x[((n * xs.c() + ci) * xs.h() + iy) * xs.w() + ix];
              }
        }
  return std::vector<float>(dw.begin(), dw.end());
}

}  // namespace facetool::testing
