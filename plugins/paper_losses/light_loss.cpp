// E_L through the 9x9 Gram matrix of the SH basis over the 64,000 illumination-loss directions.
#include "plugins/paper_losses/light_loss.h"

#include <vector>

#include "core/sh/sh_gram.h"
#include "core/util/error.h"

namespace facetool::paper_losses {

ag::Variable light_loss(const ag::Variable& predicted, const ag::Variable& target) {
  const Shape& s = predicted.shape();
  check(s.rank() == 2 && s[1] == 27, "light loss: expected predicted light [N,27], got ", s.str());
  check(target.shape() == s, "light loss: target light ", target.shape().str(),
        " does not match the predicted ", s.str());
  const std::vector<float> p = predicted.value().to_host(), t = target.value().to_host();
  const auto& g = sh::illumination_gram_matrix();
  const int64_t rows = s[0] * 3;
  // gd = G d per row, kept for the backward pass.
  std::vector<double> d(p.size()), gd(p.size());
  double total = 0.0;
  for (size_t k = 0; k < p.size(); ++k) d[k] = double(p[k]) - double(t[k]);
  for (int64_t r = 0; r < rows; ++r)
    for (int i = 0; i < 9; ++i) {
      double acc = 0.0;
      for (int j = 0; j < 9; ++j) acc += g[i][j] * d[r * 9 + j];
      gd[r * 9 + i] = acc;
      total += d[r * 9 + i] * acc;
    }
  const double norm = 1.0 / static_cast<double>(rows);
  Tensor value = Tensor::from_host(predicted.backend(), Shape{1},
                                   {static_cast<float>(total * norm)});
  return ag::make_result(
      value, "light_loss", {predicted, target},
      [gd, norm](const Tensor& grad, const std::vector<ag::GradTarget>& targets) {
        const double scale = 2.0 * norm * double(grad.to_host()[0]);
        for (size_t k = 0; k < 2 && k < targets.size(); ++k) {
          if (!targets[k]) continue;
          const double sign = k == 0 ? 1.0 : -1.0;
          std::vector<float> out =
              targets[k].accumulate ? targets[k].tensor->to_host() : std::vector<float>(gd.size(), 0.0f);
          for (size_t i = 0; i < gd.size(); ++i)
            out[i] = static_cast<float>(double(out[i]) + sign * scale * gd[i]);
          targets[k].tensor->copy_from_host(out);
        }
      });
}

}  // namespace facetool::paper_losses
