// Independent double-precision loss terms for the loss-plugin tests: quadrature render, plain MSE.
#pragma once

#include <string>
#include <vector>

namespace facetool::testing {

// One set of components in host layout: albedo [N,3,H,W], normal [N,3,H,W] (any length),
// visibility [N,9,H,W], light [N,27].
struct HostParts {
  std::vector<double> albedo, normal, visibility, light;
};

struct HostBatch {
  int64_t n = 0, h = 0, w = 0;
  HostParts target;
  std::vector<double> image;  // [N,3,H,W]
  std::vector<double> mask;   // [N,1,H,W], 0 or 1
};

// rho / pi * integral over the sphere of L~ v~ c~ (Gauss product quadrature, exact for these
// degree-6 polynomials), c~ the clamped cosine about the normalised normal by the zonal formula.
std::vector<double> reference_render(const HostBatch& b, const HostParts& parts);
// sum over masked pixels and channels of (x - y)^2 / (channels * masked pixels).
double reference_masked_mse(const HostBatch& b, const std::vector<double>& x,
                            const std::vector<double>& y, int channels);
// 1 / (3 N M) sum over images, channels and the M = 64,000 Fibonacci directions of the squared
// difference of the two lights' values, summed explicitly direction by direction.
double reference_light_loss(const std::vector<double>& a, const std::vector<double>& b);

// The named paper term evaluated from scratch: `predicted` for the network's parts.
double reference_term(const std::string& term, const HostBatch& b, const HostParts& predicted);

}  // namespace facetool::testing
