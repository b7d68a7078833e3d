// The guided filter against a plain O(r^2)-per-pixel evaluation of He et al.'s formulas, and its
// limits: a flat guide gives the box mean, a guide equal to the target gives nearly the target.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/util/error.h"
#include "libs/image/guided_filter.h"
#include "tests/support/test_support.h"

namespace facetool {
namespace {

// Plain evaluation: every window's statistics by direct sums over its (clipped) pixels. Also
// gives the averaged coefficients (mean of a_k and of b_k over the windows holding each pixel).
std::vector<float> reference(const std::vector<float>& I, const std::vector<float>& p, int channels, int w,
                             int h, int r, double eps, GuidedCoefficients* coefficients = nullptr) {
  const int n = w * h;
  auto window = [&](int x, int y, auto&& visit) {
    for (int j = std::max(0, y - r); j <= std::min(h - 1, y + r); ++j)
      for (int i = std::max(0, x - r); i <= std::min(w - 1, x + r); ++i) visit(j * w + i);
  };
  std::vector<float> out(static_cast<size_t>(channels) * n);
  if (coefficients) {
    coefficients->a.assign(out.size(), 0.0f);
    coefficients->b.assign(out.size(), 0.0f);
  }
  for (int c = 0; c < channels; ++c) {
    std::vector<double> a(n), b(n);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double si = 0, sp = 0, sii = 0, sip = 0;
        int count = 0;
        window(x, y, [&](int k) {
          si += I[k];
          sp += p[c * n + k];
          sii += static_cast<double>(I[k]) * I[k];
          sip += static_cast<double>(I[k]) * p[c * n + k];
          ++count;
        });
        const double mi = si / count, mp = sp / count;
        const double var = sii / count - mi * mi, cov = sip / count - mi * mp;
        a[y * w + x] = cov / (var + eps);
        b[y * w + x] = mp - a[y * w + x] * mi;
      }
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double q = 0, sa = 0, sb = 0;
        int count = 0;
        window(x, y, [&](int k) {
          q += a[k] * I[y * w + x] + b[k];
          sa += a[k];
          sb += b[k];
          ++count;
        });
        out[c * n + y * w + x] = static_cast<float>(q / count);
        if (coefficients) {
          coefficients->a[c * n + y * w + x] = static_cast<float>(sa / count);
          coefficients->b[c * n + y * w + x] = static_cast<float>(sb / count);
        }
      }
  }
  return out;
}

TEST(GuidedFilter, MatchesThePlainEvaluationOnRandomImages) {
  struct Case {
    int w, h, r, channels;
    double eps;
  };
  for (const Case& t : {Case{13, 9, 2, 2, 1e-2}, Case{7, 11, 1, 3, 1e-3}, Case{5, 4, 3, 1, 0.1},
                        Case{10, 10, 0, 1, 1e-2}}) {
    const std::vector<float> I = testing::random_values(t.w * t.h, 11 + t.w, 0.0f, 1.0f);
    const std::vector<float> p = testing::random_values(t.channels * t.w * t.h, 12 + t.h, -1.0f, 1.0f);
    const std::vector<float> got = guided_filter(I, p, t.channels, t.w, t.h, t.r, t.eps);
    GuidedCoefficients want_k;
    const std::vector<float> want = reference(I, p, t.channels, t.w, t.h, t.r, t.eps, &want_k);
    const GuidedCoefficients got_k = guided_coefficients(I, p, t.channels, t.w, t.h, t.r, t.eps);
    ASSERT_EQ(got.size(), want.size());
    for (size_t i = 0; i < got.size(); ++i) {
      EXPECT_NEAR(got[i], want[i], 1e-5) << t.w << "x" << t.h << " r " << t.r << " at " << i;
      EXPECT_NEAR(got_k.a[i], want_k.a[i], 1e-4 * (1 + std::abs(want_k.a[i]))) << "a at " << i;
      EXPECT_NEAR(got_k.b[i], want_k.b[i], 1e-4 * (1 + std::abs(want_k.b[i]))) << "b at " << i;
    }
  }
}

TEST(GuidedFilter, FlatGuideGivesTheBoxMeanTwiceAndTheTargetAsGuideKeepsIt) {
  const int w = 9, h = 8, r = 2;
  const std::vector<float> p = testing::random_values(w * h, 21, 0.0f, 1.0f);
  const std::vector<float> flat(w * h, 0.5f);
  const std::vector<float> smoothed = guided_filter(flat, p, 1, w, h, r, 1e-3);
  // var = 0: a = 0, b_k = the window's mean of p, and q = the mean of those over the windows.
  auto box = [&](const std::vector<double>& v) {
    std::vector<double> out(v.size());
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double sum = 0;
        int count = 0;
        for (int j = std::max(0, y - r); j <= std::min(h - 1, y + r); ++j)
          for (int i = std::max(0, x - r); i <= std::min(w - 1, x + r); ++i, ++count) sum += v[j * w + i];
        out[y * w + x] = sum / count;
      }
    return out;
  };
  const std::vector<double> twice = box(box(std::vector<double>(p.begin(), p.end())));
  for (int i = 0; i < w * h; ++i) EXPECT_NEAR(smoothed[i], twice[i], 1e-5);
  // Guide = target and a tiny epsilon: a = 1, b = 0 in every window, q = p.
  const std::vector<float> kept = guided_filter(p, p, 1, w, h, r, 1e-9);
  for (int i = 0; i < w * h; ++i) EXPECT_NEAR(kept[i], p[i], 1e-4);
}

TEST(GuidedFilter, RefusesMismatchedSizes) {
  EXPECT_THROW(guided_filter(std::vector<float>(6), std::vector<float>(5), 1, 3, 2, 1, 1e-3), Error);
  EXPECT_THROW(guided_filter(std::vector<float>(6), std::vector<float>(6), 1, 3, 2, -1, 1e-3), Error);
  EXPECT_THROW(guided_filter(std::vector<float>(6), std::vector<float>(6), 1, 3, 2, 1, 0.0), Error);
}

}  // namespace
}  // namespace facetool
