// Alternating linear least squares for the SH light and a locally constant albedo.
#include "libs/fit/fit_shading.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

#include "core/util/error.h"

namespace facetool {

namespace {
constexpr double kPi = 3.14159265358979323846;

// Box sum of planar values over a (2r+1)^2 window (summed-area table).
std::vector<double> box_sum(const std::vector<double>& v, int w, int h, int r) {
  std::vector<double> s(static_cast<size_t>(w + 1) * (h + 1), 0.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      s[static_cast<size_t>(y + 1) * (w + 1) + x + 1] = v[static_cast<size_t>(y) * w + x] +
                                                       s[static_cast<size_t>(y) * (w + 1) + x + 1] +
                                                       s[static_cast<size_t>(y + 1) * (w + 1) + x] -
                                                       s[static_cast<size_t>(y) * (w + 1) + x];
  std::vector<double> out(v.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int x0 = std::max(0, x - r), x1 = std::min(w, x + r + 1), y0 = std::max(0, y - r), y1 = std::min(h, y + r + 1);
      out[static_cast<size_t>(y) * w + x] = s[static_cast<size_t>(y1) * (w + 1) + x1] - s[static_cast<size_t>(y0) * (w + 1) + x1] -
                                           s[static_cast<size_t>(y1) * (w + 1) + x0] + s[static_cast<size_t>(y0) * (w + 1) + x0];
    }
  return out;
}
}  // namespace

ShadingSolve solve_light_and_albedo(const std::vector<float>& image, const std::vector<float>& normal,
                                    const std::vector<float>& visibility, const std::vector<uint8_t>& mask,
                                    int width, int height, const ShadingSolveSettings& settings) {
  const size_t plane = static_cast<size_t>(width) * height;
  check(image.size() == 3 * plane && normal.size() == 3 * plane && visibility.size() == 9 * plane &&
            mask.size() == plane,
        "solve_light_and_albedo: buffers do not match ", width, "x", height);
  std::vector<size_t> pixels;
  for (size_t p = 0; p < plane; ++p)
    if (mask[p]) pixels.push_back(p);
  check(pixels.size() >= 27, "solve_light_and_albedo: the fitted face covers only ", pixels.size(),
        " pixels; too few for 27 light coefficients");
  const std::vector<double> t = transfer_coefficients(normal, visibility, mask, plane);
  const int radius = settings.albedo_radius > 0 ? settings.albedo_radius : std::max(1, width / 40);
  ShadingSolve out;
  out.albedo.assign(3 * plane, 0.0f);
  std::vector<double> albedo(3 * plane, settings.mean_albedo);
  const Eigen::Index n = static_cast<Eigen::Index>(pixels.size());
  for (int round = 0; round < std::max(1, settings.rounds); ++round) {
    // Light: I_c(p) = sum_i L_ci (albedo_c(p) transfer_i(p) / pi), per channel.
    for (int c = 0; c < 3; ++c) {
      Eigen::MatrixXd a(n, 9);
      Eigen::VectorXd b(n);
      for (Eigen::Index r = 0; r < n; ++r) {
        const size_t p = pixels[r];
        for (int i = 0; i < 9; ++i) a(r, i) = albedo[c * plane + p] * t[i * plane + p] / kPi;
        b(r) = image[c * plane + p];
      }
      // Normal equations with a ridge on the orders above the DC (relative to the system's
      // mean diagonal): on a face the normals span less than a hemisphere and the DC and
      // first-order terms are nearly collinear; the ridge keeps the light plausible.
      Eigen::MatrixXd ata = a.transpose() * a;
      const double ridge = settings.light_ridge * ata.trace() / 9.0;
      for (int i = 1; i < 9; ++i) ata(i, i) += ridge;
      const Eigen::VectorXd l = ata.ldlt().solve(a.transpose() * b);
      for (int i = 0; i < 9; ++i) out.light[c * 9 + i] = l(i);
    }
    // Albedo: per channel, the locally constant a minimising sum over a window of
    // (I - a S)^2, S the shading with unit albedo: a = box(I S) / box(S S).
    for (int c = 0; c < 3; ++c) {
      std::vector<double> is(plane, 0.0), ss(plane, 0.0);
      for (size_t p : pixels) {
        double s = 0;
        for (int i = 0; i < 9; ++i) s += out.light[c * 9 + i] * t[i * plane + p] / kPi;
        is[p] = image[c * plane + p] * s;
        ss[p] = s * s;
      }
      const std::vector<double> num = box_sum(is, width, height, radius), den = box_sum(ss, width, height, radius);
      for (size_t p : pixels) {
        albedo[c * plane + p] = den[p] > 1e-12 ? num[p] / den[p] : 0.0;
      }
    }
  }
  // Fix the ambiguity (albedo_c x k_c, light_c / k_c, per channel): the light's DC term is the
  // same in every channel (a white light on average: the colour is the albedo's), and the mean
  // albedo over the pixels and channels is settings.mean_albedo.
  const double dc = (out.light[0] + out.light[9] + out.light[18]) / 3.0;
  double sum = 0;
  for (int c = 0; c < 3; ++c) {
    const double g = dc != 0.0 && out.light[c * 9] != 0.0 ? out.light[c * 9] / dc : 1.0;
    for (int i = 0; i < 9; ++i) out.light[c * 9 + i] /= g;
    for (size_t p : pixels) {
      albedo[c * plane + p] *= g;
      sum += albedo[c * plane + p];
    }
  }
  const double mean = sum / (3.0 * pixels.size());
  if (mean > 0) {
    const double k = settings.mean_albedo / mean;
    for (double& a : albedo) a *= k;
    for (double& l : out.light) l /= k;
  }
  double sq = 0;
  for (int c = 0; c < 3; ++c)
    for (size_t p : pixels) {
      double s = 0;
      for (int i = 0; i < 9; ++i) s += out.light[c * 9 + i] * t[i * plane + p] / kPi;
      const double a = std::clamp(albedo[c * plane + p], 0.0, 1.0);
      out.albedo[c * plane + p] = static_cast<float>(a);
      sq += std::pow(image[c * plane + p] - a * s, 2);
    }
  out.rms_residual = std::sqrt(sq / (3.0 * pixels.size()));
  return out;
}

}  // namespace facetool
