// Deterministic random numbers for the generator: the same seed gives the same stream on every
// platform and thread count (no std:: distributions, whose output is implementation-defined).
#pragma once

#include <cstdint>

namespace facetool {

// SplitMix64 step: a well-mixed 64-bit value from `state` (also used to derive seeds).
uint64_t splitmix64(uint64_t& state);
// A seed for sub-stream `stream` of `seed` (e.g. one per sample, then one per purpose).
uint64_t derive_seed(uint64_t seed, uint64_t stream);

// xoshiro256** generator seeded through SplitMix64.
class Random {
 public:
  explicit Random(uint64_t seed);

  uint64_t next_u64();
  // Uniform in [0, 1) with 53 random bits.
  double uniform();
  double uniform(double low, double high) { return low + (high - low) * uniform(); }
  // Uniform integer in [0, count); count must be > 0.
  uint64_t index(uint64_t count);
  // Standard normal by Box-Muller (one value per call, no caching: streams stay simple).
  double normal();
  // Standard normal restricted to [-limit, limit] by resampling (limit <= 0: no limit).
  // Throws facetool::Error for NaN and for 0 < limit < kMinTruncation (it would never end).
  static constexpr double kMinTruncation = 0.01;
  double truncated_normal(double limit);
  bool bernoulli(double probability) { return uniform() < probability; }

 private:
  uint64_t state_[4];
};

}  // namespace facetool
