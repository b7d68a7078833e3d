// The mirrored-input augmentation: which rows are mirrored, what every tensor becomes, the shading
// of a mirrored sample (the mirror of the original's), the config key.
#include <gtest/gtest.h>

#include <cmath>

#include "core/backend/registry.h"
#include "core/sh/pixel_transfer.h"
#include "core/util/error.h"
#include "libs/train/grey_inputs.h"
#include "libs/train/mirrored_inputs.h"
#include "libs/train/relit_inputs.h"
#include "libs/train/training_config.h"
#include "tests/support/test_support.h"

namespace facetool {
namespace {

Backend& cpu() { return get_backend("cpu"); }

SyntheticBatch random_batch(int n, int h, int w, bool prior) {
  SyntheticBatch b;
  b.image = testing::random_tensor(cpu(), Shape{n, 3, h, w}, 1, 0.0f, 1.0f);
  b.albedo = testing::random_tensor(cpu(), Shape{n, 3, h, w}, 2, 0.0f, 1.0f);
  b.normal = testing::random_tensor(cpu(), Shape{n, 3, h, w}, 3);
  b.mask = testing::random_tensor(cpu(), Shape{n, 1, h, w}, 4, 0.0f, 1.0f);
  b.visibility = testing::random_tensor(cpu(), Shape{n, 9, h, w}, 5);
  b.light = testing::random_tensor(cpu(), Shape{n, 27}, 6);
  if (prior) b.prior = testing::random_tensor(cpu(), Shape{n, 3, h, w}, 7);
  return b;
}

// Written out here, not through the code under test: SH functions odd in x are x, xy and xz.
float sign_of(const char* what, int channel) {
  const std::string w = what;
  if (w == "normal" || w == "prior") return channel == 0 ? -1.0f : 1.0f;
  if (w == "visibility") return channel == 3 || channel == 4 || channel == 7 ? -1.0f : 1.0f;
  return 1.0f;
}

// Every row mirrored (an odd width, so the middle column keeps its place): each map read at the
// mirrored column, the signs above applied; a fraction of 0 changes nothing; an absent prior stays absent.
TEST(MirroredInputs, EveryTensorIsFlippedWithItsSigns) {
  const int n = 2, h = 3, w = 5;
  for (bool prior : {false, true}) {
    const SyntheticBatch before = random_batch(n, h, w, prior);
    SyntheticBatch same = before;
    mirror_some_rows(same, 1, 0, 0, 0.0);
    EXPECT_EQ(same.image.to_host(), before.image.to_host());
    EXPECT_EQ(same.light.to_host(), before.light.to_host());
    SyntheticBatch after = before;
    mirror_some_rows(after, 1, 0, 0, 1.0);
    EXPECT_EQ(after.prior.defined(), prior);
    const std::pair<const char*, Tensor SyntheticBatch::*> maps[] = {
        {"image", &SyntheticBatch::image}, {"albedo", &SyntheticBatch::albedo}, {"normal", &SyntheticBatch::normal},
        {"mask", &SyntheticBatch::mask}, {"visibility", &SyntheticBatch::visibility}, {"prior", &SyntheticBatch::prior}};
    for (const auto& [name, member] : maps) {
      if (!(before.*member).defined()) continue;
      const std::vector<float> a = (before.*member).to_host(), b = (after.*member).to_host();
      const int c = static_cast<int>((before.*member).shape().c());
      for (int k = 0; k < n; ++k)
        for (int ch = 0; ch < c; ++ch)
          for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
              EXPECT_EQ(b[((k * c + ch) * h + y) * w + x], sign_of(name, ch) * a[((k * c + ch) * h + y) * w + (w - 1 - x)])
                  << name << " " << ch;
    }
    const std::vector<float> la = before.light.to_host(), lb = after.light.to_host();
    for (int k = 0; k < n * 27; ++k) EXPECT_EQ(lb[k], sign_of("visibility", k % 9) * la[k]) << k;
  }
}

// The renderer's shading of a mirrored sample (its normals, visibility and light through the
// triple product, core/sh/pixel_transfer.h) is the mirror of the original's: the signs agree
// with the SH functions themselves.
TEST(MirroredInputs, AMirroredSampleShadesAsTheMirrorOfTheOriginal) {
  const int h = 4, w = 6;
  const size_t plane = static_cast<size_t>(h) * w;
  SyntheticBatch before = random_batch(1, h, w, false);
  std::vector<float> normal = before.normal.to_host();
  for (size_t p = 0; p < plane; ++p) {  // unit normals facing the camera
    normal[2 * plane + p] = std::abs(normal[2 * plane + p]) + 0.5f;
    const float len = std::sqrt(normal[p] * normal[p] + normal[plane + p] * normal[plane + p] +
                                normal[2 * plane + p] * normal[2 * plane + p]);
    for (int c = 0; c < 3; ++c) normal[c * plane + p] /= len;
  }
  before.normal = Tensor::from_host(cpu(), before.normal.shape(), normal);
  SyntheticBatch after = before;
  mirror_some_rows(after, 1, 0, 0, 1.0);
  auto shading = [&](const SyntheticBatch& b) {
    const std::vector<uint8_t> all(plane, 1);
    const std::vector<double> t = transfer_coefficients(b.normal.to_host(), b.visibility.to_host(), all, plane);
    const std::vector<float> light = b.light.to_host();
    std::vector<double> s(3 * plane, 0.0);
    for (int c = 0; c < 3; ++c)
      for (size_t p = 0; p < plane; ++p)
        for (int i = 0; i < 9; ++i) s[c * plane + p] += light[c * 9 + i] * t[i * plane + p];
    return s;
  };
  const std::vector<double> a = shading(before), b = shading(after);
  double largest = 0;
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        EXPECT_NEAR(b[c * plane + y * w + x], a[c * plane + y * w + (w - 1 - x)], 1e-4) << c << " " << y << " " << x;
        largest = std::max(largest, std::abs(b[c * plane + y * w + x] - a[c * plane + y * w + x]));
      }
  EXPECT_GT(largest, 1e-2);  // and it is not the original's unmirrored
}

// About `fraction` of the rows, the same ones for the same arguments, a slice's rows as the
// whole batch's; not the grey or relit rows' draw.
TEST(MirroredInputs, RowsArePickedByTheirOwnDraw) {
  int picked = 0, same_as_grey = 0, same_as_relit = 0;
  const int rows = 20000;
  for (int r = 0; r < rows; ++r) {
    const bool m = mirrored_row(5, 7, 1, r, 0.5);
    EXPECT_EQ(m, mirrored_row(5, 7, 1, r, 0.5));
    picked += m;
    same_as_grey += m == grey_row(5, 7, 1, r, 0.5);
    same_as_relit += m == relit_row(5, 7, 1, r, 0.5);
  }
  EXPECT_NEAR(picked / double(rows), 0.5, 0.02);
  EXPECT_NEAR(same_as_grey / double(rows), 0.5, 0.02);  // independent draws agree half the time
  EXPECT_NEAR(same_as_relit / double(rows), 0.5, 0.02);
  SyntheticBatch whole = random_batch(6, 2, 3, false), slice = random_batch(6, 2, 3, false);
  const std::vector<float> before = whole.image.to_host();
  mirror_some_rows(whole, 9, 2, 0, 0.5, 10);
  const std::vector<float> after = whole.image.to_host();
  for (int k = 0; k < 6; ++k) {
    bool changed = false;
    for (int i = 0; i < 18; ++i) changed |= after[k * 18 + i] != before[k * 18 + i];
    EXPECT_EQ(changed, mirrored_row(9, 2, 0, 10 + k, 0.5)) << k;
  }
}

TEST(MirroredInputs, TheSourceKeyIsAFraction) {
  const std::string head = R"({"name": "x", "steps": 1, "sources": [{"name": "s", "directory": "d", )";
  const std::string tail = R"("terms": {"albedo": 1}}]})";
  EXPECT_EQ(parse_training_config(head + tail, "a.json").sources[0].mirror_fraction, 0.0);
  EXPECT_EQ(parse_training_config(head + R"("kind": "real", "mirror_fraction": 0.5, )" + tail, "a.json").sources[0].mirror_fraction, 0.5);
  try {
    parse_training_config(head + R"("mirror_fraction": -0.1, )" + tail, "b.json");
    ADD_FAILURE() << "a negative fraction accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mirror_fraction"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace facetool
