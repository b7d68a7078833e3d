// Double-precision reference of every paper loss term, written without the plugin's code paths.
#include "loss_reference.h"

#include <cmath>
#include <stdexcept>

#include "core/sh/clamped_cosine.h"
#include "core/sh/sh_basis.h"
#include "core/sh/sh_eval.h"
#include "core/sh/sphere_samples.h"
#include "sphere_quadrature.h"
#include "core/util/math_constants.h"

namespace facetool::testing {

std::vector<double> reference_render(const HostBatch& b, const HostParts& parts) {
  const int64_t pixels = b.h * b.w;
  std::vector<double> image(b.n * 3 * pixels, 0.0);
  for (int64_t i = 0; i < b.n; ++i)
    for (int64_t p = 0; p < pixels; ++p) {
      if (b.mask[i * pixels + p] <= 0.5) continue;
      const sh::Vec3 n{parts.normal[(i * 3 + 0) * pixels + p], parts.normal[(i * 3 + 1) * pixels + p],
                       parts.normal[(i * 3 + 2) * pixels + p]};
      const sh::ShCoeffs c = sh::clamped_cosine_coeffs(n);
      sh::ShCoeffs v;
      for (int j = 0; j < 9; ++j) v[j] = parts.visibility[(i * 9 + j) * pixels + p];
      for (int ch = 0; ch < 3; ++ch) {
        sh::ShCoeffs l;
        for (int k = 0; k < 9; ++k) l[k] = parts.light[i * 27 + ch * 9 + k];
        const double integral = integrate_sphere(
            [&](const sh::Vec3& w) { return sh::sh_eval(l, w) * sh::sh_eval(v, w) * sh::sh_eval(c, w); },
            4, 8);
        const int64_t at = (i * 3 + ch) * pixels + p;
        image[at] = parts.albedo[at] * integral / kPi;
      }
    }
  return image;
}

double reference_masked_mse(const HostBatch& b, const std::vector<double>& x,
                            const std::vector<double>& y, int channels) {
  const int64_t pixels = b.h * b.w;
  double error = 0.0, count = 0.0;
  for (int64_t i = 0; i < b.n; ++i)
    for (int64_t p = 0; p < pixels; ++p) {
      if (b.mask[i * pixels + p] <= 0.5) continue;
      count += 1.0;
      for (int c = 0; c < channels; ++c) {
        const double d = x[(i * channels + c) * pixels + p] - y[(i * channels + c) * pixels + p];
        error += d * d;
      }
    }
  return error / (channels * count);
}

double reference_light_loss(const std::vector<double>& a, const std::vector<double>& b) {
  static const std::vector<sh::Vec3> dirs = sh::fibonacci_sphere(64000);
  const size_t rows = a.size() / 9;
  double total = 0.0;
  for (const sh::Vec3& w : dirs) {
    double y[9];
    sh::sh_basis(w[0], w[1], w[2], y);
    for (size_t r = 0; r < rows; ++r) {
      double va = 0.0, vb = 0.0;
      for (int k = 0; k < 9; ++k) {
        va += a[r * 9 + k] * y[k];
        vb += b[r * 9 + k] * y[k];
      }
      total += (va - vb) * (va - vb);
    }
  }
  return total / (static_cast<double>(rows) * static_cast<double>(dirs.size()));
}

double reference_term(const std::string& term, const HostBatch& b, const HostParts& pred) {
  if (term == "albedo") return reference_masked_mse(b, pred.albedo, b.target.albedo, 3);
  if (term == "normal") return reference_masked_mse(b, pred.normal, b.target.normal, 3);
  if (term == "visibility") return reference_masked_mse(b, pred.visibility, b.target.visibility, 9);
  if (term == "light") return reference_light_loss(pred.light, b.target.light);
  HostParts parts = b.target;
  if (term == "recon_albedo") parts.albedo = pred.albedo;
  else if (term == "recon_normal") parts.normal = pred.normal;
  else if (term == "recon_visibility") parts.visibility = pred.visibility;
  else if (term == "recon_light") parts.light = pred.light;
  else if (term == "recon_albedo_normal_light" || term == "recon_all") parts = pred;
  else throw std::runtime_error("reference_term: unknown term " + term);
  return reference_masked_mse(b, reference_render(b, parts), b.image, 3);
}

}  // namespace facetool::testing
