// The guided filter with box means from summed-area tables.
#include "libs/image/guided_filter.h"

#include <algorithm>

#include "core/util/error.h"

namespace facetool {
namespace {

// Means over the clipped (2r+1)^2 window of every pixel of a w x h plane.
class BoxMean {
 public:
  BoxMean(int w, int h, int r) : w_(w), h_(h), r_(r), sum_(static_cast<size_t>(w + 1) * (h + 1)) {}

  std::vector<double> operator()(const std::vector<double>& v) {
    std::fill(sum_.begin(), sum_.end(), 0.0);
    for (int y = 0; y < h_; ++y) {
      double row = 0;
      for (int x = 0; x < w_; ++x) {
        row += v[static_cast<size_t>(y) * w_ + x];
        at(x + 1, y + 1) = at(x + 1, y) + row;
      }
    }
    std::vector<double> out(static_cast<size_t>(w_) * h_);
    for (int y = 0; y < h_; ++y) {
      const int y0 = std::max(0, y - r_), y1 = std::min(h_, y + r_ + 1);
      for (int x = 0; x < w_; ++x) {
        const int x0 = std::max(0, x - r_), x1 = std::min(w_, x + r_ + 1);
        const double s = at(x1, y1) - at(x0, y1) - at(x1, y0) + at(x0, y0);
        out[static_cast<size_t>(y) * w_ + x] = s / ((x1 - x0) * (y1 - y0));
      }
    }
    return out;
  }

 private:
  double& at(int x, int y) { return sum_[static_cast<size_t>(y) * (w_ + 1) + x]; }
  int w_, h_, r_;
  std::vector<double> sum_;
};

}  // namespace

GuidedCoefficients guided_coefficients(const std::vector<float>& guide, const std::vector<float>& target,
                                       int channels, int w, int h, int r, double epsilon) {
  const size_t plane = static_cast<size_t>(w) * h;
  check(w > 0 && h > 0 && channels > 0, "guided filter: empty image (", w, "x", h, ", ", channels, " channels)");
  check(guide.size() == plane && target.size() == plane * channels, "guided filter: a guide of ",
        guide.size(), " values and a target of ", target.size(), " for ", channels, " planes of ", w, "x", h);
  check(r >= 0 && epsilon > 0, "guided filter: radius ", r, " must be >= 0 and epsilon ", epsilon, " > 0");
  BoxMean mean(w, h, r);
  const std::vector<double> I(guide.begin(), guide.end());
  std::vector<double> II(plane);
  for (size_t i = 0; i < plane; ++i) II[i] = I[i] * I[i];
  const std::vector<double> mean_I = mean(I), mean_II = mean(II);
  GuidedCoefficients out;
  out.a.resize(target.size());
  out.b.resize(target.size());
  std::vector<double> p(plane), Ip(plane), a(plane), b(plane);
  for (int c = 0; c < channels; ++c) {
    for (size_t i = 0; i < plane; ++i) {
      p[i] = target[c * plane + i];
      Ip[i] = I[i] * p[i];
    }
    const std::vector<double> mean_p = mean(p), mean_Ip = mean(Ip);
    for (size_t i = 0; i < plane; ++i) {
      const double var = mean_II[i] - mean_I[i] * mean_I[i];
      const double cov = mean_Ip[i] - mean_I[i] * mean_p[i];
      a[i] = cov / (var + epsilon);
      b[i] = mean_p[i] - a[i] * mean_I[i];
    }
    const std::vector<double> mean_a = mean(a), mean_b = mean(b);
    for (size_t i = 0; i < plane; ++i) {
      out.a[c * plane + i] = static_cast<float>(mean_a[i]);
      out.b[c * plane + i] = static_cast<float>(mean_b[i]);
    }
  }
  return out;
}

std::vector<float> guided_filter(const std::vector<float>& guide, const std::vector<float>& target,
                                 int channels, int w, int h, int r, double epsilon) {
  const GuidedCoefficients k = guided_coefficients(guide, target, channels, w, h, r, epsilon);
  const size_t plane = static_cast<size_t>(w) * h;
  std::vector<float> out(target.size());
  for (int c = 0; c < channels; ++c)
    for (size_t i = 0; i < plane; ++i) out[c * plane + i] = k.a[c * plane + i] * guide[i] + k.b[c * plane + i];
  return out;
}

}  // namespace facetool
