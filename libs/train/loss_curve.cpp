// Plotting the loss curve into an RGB image with plain line drawing.
#include "libs/train/loss_curve.h"

#include <algorithm>
#include <cmath>

#include "libs/io/image_io.h"

namespace facetool {
namespace {

void put(RgbImage& im, int x, int y, const float rgb[3]) {
  if (x < 0 || y < 0 || x >= im.width || y >= im.height) return;
  std::copy(rgb, rgb + 3, im.at(x, y));
}

void line(RgbImage& im, double x0, double y0, double x1, double y1, const float rgb[3]) {
  const int n = static_cast<int>(std::max(std::fabs(x1 - x0), std::fabs(y1 - y0))) + 1;
  for (int i = 0; i <= n; ++i) {
    const double t = static_cast<double>(i) / n;
    put(im, static_cast<int>(std::lround(x0 + t * (x1 - x0))),
        static_cast<int>(std::lround(y0 + t * (y1 - y0))), rgb);
  }
}

}  // namespace

void write_loss_curve(const std::string& path, const std::vector<std::pair<double, double>>& points,
                      int width, int height) {
  RgbImage im;
  im.width = width;
  im.height = height;
  im.pixels.assign(static_cast<size_t>(width) * height * 3, 1.0f);
  const float axis[3] = {0.2f, 0.2f, 0.2f}, grid[3] = {0.85f, 0.85f, 0.85f},
              curve[3] = {0.1f, 0.3f, 0.8f};
  const int left = 40, right = width - 10, top = 10, bottom = height - 20;
  std::vector<std::pair<double, double>> kept;
  for (const auto& [x, y] : points)
    if (y > 0.0 && std::isfinite(y)) kept.emplace_back(x, std::log10(y));
  if (kept.size() >= 2) {
    double x_lo = kept.front().first, x_hi = kept.back().first;
    double y_lo = kept[0].second, y_hi = kept[0].second;
    for (const auto& p : kept) y_lo = std::min(y_lo, p.second), y_hi = std::max(y_hi, p.second);
    y_lo = std::floor(y_lo);
    y_hi = std::max(std::ceil(y_hi), y_lo + 1.0);
    if (x_hi <= x_lo) x_hi = x_lo + 1.0;
    auto px = [&](double x) { return left + (x - x_lo) / (x_hi - x_lo) * (right - left); };
    auto py = [&](double y) { return bottom - (y - y_lo) / (y_hi - y_lo) * (bottom - top); };
    for (double d = y_lo; d <= y_hi; d += 1.0) line(im, left, py(d), right, py(d), grid);
    for (size_t k = 1; k < kept.size(); ++k)
      line(im, px(kept[k - 1].first), py(kept[k - 1].second), px(kept[k].first),
           py(kept[k].second), curve);
  }
  line(im, left, top, left, bottom, axis);
  line(im, left, bottom, right, bottom, axis);
  write_png_atomically(path, im, false);
}

}  // namespace facetool
