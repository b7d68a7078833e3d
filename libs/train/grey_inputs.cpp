// Training augmentation: a fraction of a batch's input photos turned grey (luminance in R, G, B).
#include "libs/train/grey_inputs.h"

#include <vector>

#include "core/util/error.h"
#include "libs/io/image_io.h"

namespace facetool {
namespace {

// SplitMix64's finaliser: a well-mixed 64-bit hash of one word.
uint64_t mix(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

}  // namespace

uint64_t row_hash(uint64_t seed, int64_t step, int source, int64_t row) {
  return mix(mix(mix(mix(seed) ^ static_cast<uint64_t>(step)) ^ static_cast<uint64_t>(source)) ^
             static_cast<uint64_t>(row));
}

bool row_drawn(uint64_t seed, int64_t step, int source, int64_t row, double fraction) {
  if (fraction <= 0) return false;
  if (fraction >= 1) return true;
  return static_cast<double>(row_hash(seed, step, source, row) >> 11) * 0x1.0p-53 < fraction;
}

bool grey_row(uint64_t seed, int64_t step, int source, int64_t row, double fraction) {
  return row_drawn(seed, step, source, row, fraction);
}

Tensor grey_some_rows(const Tensor& input, uint64_t seed, int64_t step, int source, double fraction,
                      int64_t first_row) {
  const Shape& s = input.shape();
  check(s.rank() == 4 && s.c() >= 3, "grey inputs: expected [N, C >= 3, H, W], got ", s.str());
  std::vector<int64_t> rows;
  for (int64_t n = 0; n < s.n(); ++n)
    if (grey_row(seed, step, source, first_row + n, fraction)) rows.push_back(n);
  if (rows.empty()) return input;
  std::vector<float> v = input.to_host();
  const size_t plane = static_cast<size_t>(s.h()) * s.w();
  for (const int64_t n : rows) {
    float* r = v.data() + static_cast<size_t>(n) * s.c() * plane;
    float* g = r + plane;
    float* b = g + plane;
    for (size_t p = 0; p < plane; ++p) {
      const float y = luminance(r[p], g[p], b[p]);
      r[p] = g[p] = b[p] = y;
    }
  }
  return Tensor::from_host(input.backend(), s, v);
}

}  // namespace facetool
