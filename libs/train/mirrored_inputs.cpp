// Training augmentation: the picked rows of a batch flipped left to right with their labels' signs.
#include "libs/train/mirrored_inputs.h"

#include <vector>

#include "core/sh/sh_basis.h"
#include "core/util/error.h"
#include "libs/image/mirror.h"
#include "libs/train/grey_inputs.h"

namespace facetool {
namespace {

constexpr uint64_t kMirrorSalt = 0x6D6972726F726564ull;  // "mirrored"

// Mirrors the rows `rows` of the [N, C, H, W] tensor `t`, channel c times sign(c).
template <typename Sign>
void flip_rows(Tensor& t, const std::vector<int64_t>& rows, Sign sign) {
  if (!t.defined() || t.numel() == 0) return;
  const Shape& s = t.shape();
  check(s.rank() == 4, "mirrored inputs: expected [N, C, H, W], got ", s.str());
  std::vector<float> values = t.to_host();
  const int64_t plane = s.h() * s.w();
  for (const int64_t n : rows)
    for (int64_t c = 0; c < s.c(); ++c)
      mirror_plane(values.data() + (n * s.c() + c) * plane, s.h(), s.w(), static_cast<float>(sign(static_cast<int>(c))));
  t = Tensor::from_host(t.backend(), s, values);
}

double keep(int) { return 1.0; }
double normal_sign(int c) { return c == 0 ? -1.0 : 1.0; }

}  // namespace

bool mirrored_row(uint64_t seed, int64_t step, int source, int64_t row, double fraction) {
  return row_drawn(seed ^ kMirrorSalt, step, source, row, fraction);
}

void mirror_some_rows(SyntheticBatch& batch, uint64_t seed, int64_t step, int source, double fraction,
                      int64_t first_row) {
  if (fraction <= 0) return;
  const Shape& s = batch.image.shape();
  check(s.rank() == 4, "mirrored inputs: expected an image [N, C, H, W], got ", s.str());
  std::vector<int64_t> rows;
  for (int64_t n = 0; n < s.n(); ++n)
    if (mirrored_row(seed, step, source, first_row + n, fraction)) rows.push_back(n);
  if (rows.empty()) return;
  flip_rows(batch.image, rows, keep);
  flip_rows(batch.albedo, rows, keep);
  flip_rows(batch.mask, rows, keep);
  flip_rows(batch.normal, rows, normal_sign);
  flip_rows(batch.prior, rows, normal_sign);  // the fit's normals (NetworkConfig::input_prior)
  flip_rows(batch.visibility, rows, sh::mirror_x_sign);
  if (!batch.light.defined() || batch.light.numel() == 0) return;
  const Shape& ls = batch.light.shape();
  check(ls.rank() == 2 && ls.dim(1) == 27, "mirrored inputs: expected a light [N, 27], got ", ls.str());
  std::vector<float> light = batch.light.to_host();
  for (const int64_t n : rows)
    for (int k = 0; k < 27; ++k) light[n * 27 + k] *= static_cast<float>(sh::mirror_x_sign(k % 9));
  batch.light = Tensor::from_host(batch.light.backend(), ls, light);
}

}  // namespace facetool
