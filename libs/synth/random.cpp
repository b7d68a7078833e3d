// SplitMix64 and xoshiro256** (public-domain algorithms by Vigna), Box-Muller normals.
#include "libs/synth/random.h"

#include "core/util/error.h"
#include "core/util/math_constants.h"

#include <cmath>

namespace facetool {
namespace {
uint64_t rotate_left(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
}  // namespace

uint64_t splitmix64(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

uint64_t derive_seed(uint64_t seed, uint64_t stream) {
  uint64_t state = seed ^ (0xD1B54A32D192ED03ull * (stream + 1));
  splitmix64(state);
  return splitmix64(state);
}

Random::Random(uint64_t seed) {
  uint64_t state = seed;
  for (uint64_t& s : state_) s = splitmix64(state);
}

uint64_t Random::next_u64() {
  const uint64_t result = rotate_left(state_[1] * 5, 7) * 9;
  const uint64_t t = state_[1] << 17;
  state_[2] ^= state_[0];
  state_[3] ^= state_[1];
  state_[1] ^= state_[2];
  state_[0] ^= state_[3];
  state_[2] ^= t;
  state_[3] = rotate_left(state_[3], 45);
  return result;
}

double Random::uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

uint64_t Random::index(uint64_t count) {
  // Rejection keeps the result exactly uniform.
  const uint64_t limit = UINT64_MAX - UINT64_MAX % count;
  uint64_t value;
  do value = next_u64();
  while (value >= limit);
  return value % count;
}

double Random::normal() {
  const double pi = kPi;
  const double u1 = 1.0 - uniform();  // (0, 1]: log is finite
  const double u2 = uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * pi * u2);
}

double Random::truncated_normal(double limit) {
  // Rejection needs about 1 / P(|x| <= limit) draws: bounded for limit >= kMinTruncation
  // (acceptance 0.8%), endless for NaN or a vanishing limit, which are refused.
  check(!std::isnan(limit) && (limit <= 0.0 || limit >= kMinTruncation),
        "truncated normal: limit ", limit, " is NaN or below ", kMinTruncation);
  if (limit <= 0.0 || std::isinf(limit)) return normal();
  for (;;) {
    const double value = normal();
    if (std::fabs(value) <= limit) return value;
  }
}

}  // namespace facetool
