// Synchronised batch norm: statistics summed over every rank of a data-parallel job by a hook.
#pragma once

#include <functional>
#include <vector>

#include "core/autograd/variable.h"
#include "core/backend/op_params.h"

namespace facetool::ag {

// Sums a vector element-wise over the ranks of the job, in place (Communicator::allreduce_sum).
using StatisticsSum = std::function<void(std::vector<double>&)>;

// While a sum is installed, ag::batch_norm in training mode normalises with the statistics of
// the global batch (every rank's rows): the forward pass sums per-channel counts, sums and
// squared deviations over the ranks; the backward pass sums sum(dy) and sum(dy * xhat) the same
// way, so K ranks compute what one process computes on the whole batch. dgamma and dbeta stay
// this rank's partial sums (the gradient allreduce adds them). Computed on the host, whatever the
// backend, with the cpu backend's arithmetic (double sums, no fused multiply-add), so that one
// process gives the cpu backend's floats exactly. An empty function restores local statistics.
void set_batch_norm_statistics_sum(StatisticsSum sum);
const StatisticsSum& batch_norm_statistics_sum();

Variable synced_batch_norm(const Variable& x, const Variable& gamma, const Variable& beta,
                           const Tensor& running_mean, const Tensor& running_var,
                           const BatchNormParams& p, const StatisticsSum& sum);

}  // namespace facetool::ag
