// The light from a face's shading: albedo detail, 9 x 9 moments, a search over directions, robust reweighting.
#include "libs/light/light_from_shading.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/sh/pixel_transfer.h"
#include "core/sh/sh_basis.h"
#include "core/sh/sphere_samples.h"
#include "core/util/math_constants.h"

namespace facetool {

namespace {

constexpr double kSaturated = 0.95;    // a linear channel above this is clipped (sRGB 250 of 255)
constexpr double kBlack = 0.002;       // a luminance below this says nothing (sensor black)
constexpr int kRounds = 4;             // the first unweighted, then Cauchy weights
constexpr double kCauchy = 2.385;      // the Cauchy scale in robust sigmas (95 % efficiency)
constexpr int kCoarseDirections = 2000;
constexpr double kMinCoarseZ = -0.5;   // the coarse search stops 120 degrees from the camera axis
constexpr int kFineDirections = 1000;
constexpr double kFineRadiusDeg = 6.0;
constexpr double kBehindDeg = 90.0;    // a light behind the plane facing the camera is warned of
constexpr double kFeatureDarkness = 0.75;  // albedo below this fraction of its blur: a dark feature
constexpr int kDetailDivisor = 32;          // the albedo's blur radius: the crop's size / this (3 px at 96)
constexpr int kPixelStride = 2;             // every second pixel of every second row is fitted
constexpr double kAmbientQuantile = 0.15;   // the ambient's ceiling: this quantile of the darkest pixels
constexpr double kDarkFace = 0.08;  // the face's median brightness below this fraction of its 99th percentile: warned of

// One fitted pixel: its transfer (divided by pi), its colours, its albedo in the fit.
struct Pixel {
  sh::ShCoeffs transfer;
  double image[3];
  double albedo[3];
};

// Per colour, the weighted moments of the model I = albedo transfer . L: G = sum w u u^T,
// b = sum w I u, q = sum w I^2 with u = albedo transfer.
struct Moments {
  double g[9][9];
  double b[9];
  double q;
};

struct Candidate {
  sh::Vec3 direction;
  double ambient[3];
  double intensity[3];
  double cost;
};

// Normalised convolution of each albedo channel with a box blur of radius r applied three times
// (close to a Gaussian of sigma r), weighted by the mask: blur(albedo mask) / blur(mask).
std::vector<double> smooth_over_mask(const float* albedo, const std::vector<double>& weight, int size, int radius) {
  const size_t plane = static_cast<size_t>(size) * size;
  auto box = [&](std::vector<double>& v) {
    std::vector<double> tmp(plane);
    for (int pass = 0; pass < 3; ++pass) {
      for (int y = 0; y < size; ++y) {  // rows
        double sum = 0;
        const double* row = v.data() + static_cast<size_t>(y) * size;
        for (int x = -radius; x <= radius; ++x) sum += row[std::clamp(x, 0, size - 1)];
        for (int x = 0; x < size; ++x) {
          tmp[static_cast<size_t>(y) * size + x] = sum;
          sum += row[std::min(x + radius + 1, size - 1)] - row[std::max(x - radius, 0)];
        }
      }
      for (int x = 0; x < size; ++x) {  // columns
        double sum = 0;
        for (int y = -radius; y <= radius; ++y) sum += tmp[static_cast<size_t>(std::clamp(y, 0, size - 1)) * size + x];
        for (int y = 0; y < size; ++y) {
          v[static_cast<size_t>(y) * size + x] = sum;
          sum += tmp[static_cast<size_t>(std::min(y + radius + 1, size - 1)) * size + x] -
                 tmp[static_cast<size_t>(std::max(y - radius, 0)) * size + x];
        }
      }
    }
  };
  std::vector<double> den = weight;
  box(den);
  std::vector<double> out(3 * plane);
  for (int c = 0; c < 3; ++c) {
    std::vector<double> num(plane);
    for (size_t p = 0; p < plane; ++p) num[p] = static_cast<double>(albedo[c * plane + p]) * weight[p];
    box(num);
    for (size_t p = 0; p < plane; ++p) out[c * plane + p] = den[p] > 1e-12 ? num[p] / den[p] : 0.0;
  }
  return out;
}

// The moments of one colour, or with `joint` of the three colours together (one white light).
Moments moments(const std::vector<Pixel>& pixels, const std::vector<double>& weight, int channel, bool joint) {
  Moments m{};
  for (size_t k = 0; k < pixels.size(); ++k) {
    const Pixel& px = pixels[k];
    const double w = weight[k];
    if (w <= 0) continue;
    const int first = joint ? 0 : channel, last = joint ? 2 : channel;
    for (int c = first; c <= last; ++c) {
      double u[9];
      for (int i = 0; i < 9; ++i) u[i] = px.albedo[c] * px.transfer[i];
      for (int i = 0; i < 9; ++i) {
        m.b[i] += w * px.image[c] * u[i];
        for (int j = i; j < 9; ++j) m.g[i][j] += w * u[i] * u[j];
      }
      m.q += w * px.image[c] * px.image[c];
    }
  }
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < i; ++j) m.g[i][j] = m.g[j][i];
  return m;
}

// min over a, s >= 0 of q - 2 (a e.b + s y.b) + (a e + s y)^T G (a e + s y), e = sqrt(4 pi) e_0
// (a uniform radiance of 1) and y = Y(d) (a unit delta towards d). Returns the cost.
double fit_direction(const Moments& m, const double y[9], double max_ambient, double& ambient, double& intensity) {
  const double e0 = std::sqrt(4.0 * kPi);
  double gy[9];
  for (int i = 0; i < 9; ++i) {
    gy[i] = 0;
    for (int j = 0; j < 9; ++j) gy[i] += m.g[i][j] * y[j];
  }
  double yb = 0, ygy = 0;
  for (int i = 0; i < 9; ++i) {
    yb += y[i] * m.b[i];
    ygy += y[i] * gy[i];
  }
  const double eb = e0 * m.b[0], ege = e0 * e0 * m.g[0][0], egy = e0 * gy[0];
  auto cost = [&](double a, double s) { return m.q - 2 * (a * eb + s * yb) + a * a * ege + 2 * a * s * egy + s * s * ygy; };
  double best_a = 0, best_s = 0, best = m.q;
  auto consider = [&](double a, double s) {
    const double c = cost(a, s);
    if (c < best) best = c, best_a = a, best_s = s;
  };
  const double det = ege * ygy - egy * egy;
  if (det > 1e-12 * std::max(1e-300, ege * ygy)) {
    const double a = (eb * ygy - yb * egy) / det, s = (yb * ege - eb * egy) / det;
    if (a >= 0 && a <= max_ambient && s >= 0) consider(a, s);
  }
  if (ygy > 0) {
    consider(0, std::max(0.0, yb / ygy));
    if (std::isfinite(max_ambient)) consider(max_ambient, std::max(0.0, (yb - max_ambient * egy) / ygy));
  }
  if (ege > 0) consider(std::clamp(eb / ege, 0.0, max_ambient), 0);
  ambient = best_a;
  intensity = best_s;
  return best;
}

Candidate evaluate(const Moments* m, const double* max_ambient, int channels, const sh::Vec3& d) {
  double y[9];
  sh::sh_basis(d[0], d[1], d[2], y);
  Candidate c{d, {0, 0, 0}, {0, 0, 0}, 0};
  for (int ch = 0; ch < channels; ++ch) c.cost += fit_direction(m[ch], y, max_ambient[ch], c.ambient[ch], c.intensity[ch]);
  return c;
}

// `count` directions within `radius_deg` of the unit `centre`, a Fibonacci lattice on the cap.
std::vector<sh::Vec3> cap_directions(const sh::Vec3& centre, double radius_deg, int count) {
  const sh::Vec3 helper = std::abs(centre[2]) < 0.9 ? sh::Vec3{0, 0, 1} : sh::Vec3{1, 0, 0};
  sh::Vec3 u{centre[1] * helper[2] - centre[2] * helper[1], centre[2] * helper[0] - centre[0] * helper[2],
             centre[0] * helper[1] - centre[1] * helper[0]};
  const double un = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (double& v : u) v /= un;
  const sh::Vec3 w{centre[1] * u[2] - centre[2] * u[1], centre[2] * u[0] - centre[0] * u[2],
                   centre[0] * u[1] - centre[1] * u[0]};
  const double zmin = std::cos(radius_deg * kPi / 180.0);
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  std::vector<sh::Vec3> out(count);
  for (int s = 0; s < count; ++s) {
    const double z = 1.0 - (1.0 - zmin) * (s + 0.5) / count, r = std::sqrt(std::max(0.0, 1 - z * z));
    const double phi = s * golden, a = r * std::cos(phi), b = r * std::sin(phi);
    for (int k = 0; k < 3; ++k) out[s][k] = z * centre[k] + a * u[k] + b * w[k];
  }
  return out;
}

const std::vector<sh::Vec3>& coarse_directions() {
  static const std::vector<sh::Vec3> dirs = [] {
    std::vector<sh::Vec3> all = sh::fibonacci_sphere(kCoarseDirections), kept;
    for (const sh::Vec3& d : all)
      if (d[2] >= kMinCoarseZ) kept.push_back(d);
    return kept;
  }();
  return dirs;
}

Candidate search(const Moments* m, const double* max_ambient, int channels) {
  Candidate best{{0, 0, 1}, {0, 0, 0}, {0, 0, 0}, INFINITY};
  for (const sh::Vec3& d : coarse_directions()) {
    const Candidate c = evaluate(m, max_ambient, channels, d);
    if (c.cost < best.cost) best = c;
  }
  for (const sh::Vec3& d : cap_directions(best.direction, kFineRadiusDeg, kFineDirections)) {
    const Candidate c = evaluate(m, max_ambient, channels, d);
    if (c.cost < best.cost) best = c;
  }
  return best;
}

// Per channel, the `quantile` over the pixels of what the distant light `best` leaves of the image,
// over albedo x the shading of a uniform unit radiance: the ambient no more than that many of the
// face's pixels are darker than (the distant light's part taken out, so that its 9 coefficients'
// ringing below zero behind the terminator counts).
void ambient_ceiling(const std::vector<Pixel>& pixels, bool joint, int channels, const Candidate& best,
                     double quantile, double* out) {
  double y[9];
  sh::sh_basis(best.direction[0], best.direction[1], best.direction[2], y);
  for (int c = 0; c < channels; ++c) {
    std::vector<double> ratio;
    for (const Pixel& px : pixels) {
      double direct = 0;
      for (int i = 0; i < 9; ++i) direct += best.intensity[c] * y[i] * px.transfer[i];
      double i = 0, u = 0;
      for (int k = joint ? 0 : c; k <= (joint ? 2 : c); ++k) {
        i += px.image[k] - px.albedo[k] * direct;
        u += px.albedo[k] * std::sqrt(4.0 * kPi) * px.transfer[0];
      }
      if (u > 1e-9) ratio.push_back(i / u);
    }
    if (ratio.empty()) continue;
    const size_t at = std::min(ratio.size() - 1, static_cast<size_t>(quantile * ratio.size()));
    std::nth_element(ratio.begin(), ratio.begin() + at, ratio.end());
    out[c] = std::max(0.0, ratio[at]);
  }
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  return v[mid];
}

}  // namespace

sh::RgbLight sh_light(const DistantLight& light) {
  double y[9];
  sh::sh_basis(light.direction[0], light.direction[1], light.direction[2], y);
  sh::RgbLight out{};
  for (int c = 0; c < 3; ++c) {
    for (int i = 0; i < 9; ++i) out[c * 9 + i] = light.intensity[c] * y[i];
    out[c * 9] += std::sqrt(4.0 * kPi) * light.ambient[c];
  }
  return out;
}

DistantLight solve_distant_light(const ShadingInputs& in) {
  DistantLight out;
  const int size = in.size;
  const size_t plane = static_cast<size_t>(size) * size;
  // The face's pixels, and the albedo the fit uses.
  std::vector<double> face(plane, 0.0);
  for (size_t p = 0; p < plane; ++p) face[p] = in.mask[p] > 0.5f ? 1.0 : 0.0;
  std::vector<double> smooth;
  double mean_albedo[3] = {0, 0, 0}, face_pixels = 0;
  for (size_t p = 0; p < plane; ++p)
    if (face[p] > 0) {
      face_pixels += 1;
      for (int c = 0; c < 3; ++c) mean_albedo[c] += in.albedo[c * plane + p];
    }
  if (face_pixels < kMinLightSolvePixels) {
    if (face_pixels > 0) out.warning = "too few face pixels to solve the light; the network's light is kept";
    return out;
  }
  for (double& a : mean_albedo) a /= face_pixels;
  {
    // The blur of the skin: a second pass leaves out the pixels far darker than the first blur
    // (brows, lashes, lips), which would darken the skin's blur around them.
    const int radius = std::max(1, size / kDetailDivisor);
    smooth = smooth_over_mask(in.albedo, face, size, radius);
    std::vector<double> skin = face;
    for (size_t p = 0; p < plane; ++p) {
      double a = 0, b = 0;
      for (int c = 0; c < 3; ++c) {
        a += in.albedo[c * plane + p];
        b += smooth[c * plane + p];
      }
      if (a < kFeatureDarkness * b) skin[p] = 0.0;
    }
    smooth = smooth_over_mask(in.albedo, skin, size, radius);
  }
  std::vector<Pixel> pixels;
  pixels.reserve(static_cast<size_t>(face_pixels));
  bool grey = true;
  for (size_t p = 0; p < plane; ++p) {
    if (face[p] <= 0) continue;
    if ((p / size) % kPixelStride != 0 || (p % size) % kPixelStride != 0) continue;
    Pixel px;
    double top = 0, lum = 0;
    for (int c = 0; c < 3; ++c) {
      px.image[c] = in.image[c * plane + p];
      top = std::max(top, px.image[c]);
      lum += px.image[c] / 3.0;
      const double a = in.albedo[c * plane + p];
      px.albedo[c] = smooth[c * plane + p] > 1e-4 ? a / smooth[c * plane + p] * mean_albedo[c] : 0.0;
    }
    const sh::Vec3 n{in.normal[p], in.normal[plane + p], in.normal[2 * plane + p]};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(top < kSaturated) || !(lum > kBlack) || !(len > 1e-6) || !std::isfinite(len)) continue;
    sh::ShCoeffs v;
    bool finite = true;
    for (int j = 0; j < 9; ++j) {
      v[j] = in.visibility[j * plane + p];
      finite = finite && std::isfinite(v[j]);
    }
    if (!finite) continue;
    px.transfer = pixel_transfer(n, v);
    for (double& t : px.transfer) t /= kPi;
    grey = grey && px.image[1] == px.image[0] && px.image[2] == px.image[0];
    pixels.push_back(px);
  }
  if (pixels.size() < kMinLightSolvePixels / (kPixelStride * kPixelStride)) {
    out.warning = "too few face pixels lit and unsaturated to solve the light; the network's light is kept";
    return out;
  }
  if (grey)  // one albedo for the three equal channels: the mean of the network's colours
    for (Pixel& px : pixels) {
      const double a = (px.albedo[0] + px.albedo[1] + px.albedo[2]) / 3.0;
      px.albedo[0] = px.albedo[1] = px.albedo[2] = a;
    }
  // One white light is fitted to the three colours together (its colour comes last): a light whose
  // ambient and distant parts differ in colour from one colour to the next tints the shadows.
  const int channels = 1;
  std::vector<double> weight(pixels.size(), 1.0);
  const double no_ceiling[3] = {INFINITY, INFINITY, INFINITY};
  Candidate best{};
  double mean_image = 0;
  for (const Pixel& px : pixels) mean_image += (px.image[0] + px.image[1] + px.image[2]) / 3.0;
  mean_image /= pixels.size();
  double sigma = 0;
  for (int round = 0; round < kRounds; ++round) {
    Moments m[3];
    for (int c = 0; c < channels; ++c) m[c] = moments(pixels, weight, c, true);
    best = search(m, no_ceiling, channels);
    for (int c = 1; c < 3; ++c) best.ambient[c] = best.ambient[0], best.intensity[c] = best.intensity[0];
    // Residuals under the light found, and Cauchy weights for the next round.
    DistantLight trial;
    trial.direction = best.direction;
    for (int c = 0; c < 3; ++c) trial.ambient[c] = best.ambient[c], trial.intensity[c] = best.intensity[c];
    const sh::RgbLight l = sh_light(trial);
    std::vector<double> residual(pixels.size()), magnitude(pixels.size());
    for (size_t k = 0; k < pixels.size(); ++k) {
      double sum = 0;
      for (int c = 0; c < 3; ++c) {
        double shade = 0;
        for (int i = 0; i < 9; ++i) shade += l[c * 9 + i] * pixels[k].transfer[i];
        sum += pixels[k].image[c] - pixels[k].albedo[c] * shade;
      }
      residual[k] = sum / 3.0;
      magnitude[k] = std::abs(residual[k]);
    }
    sigma = std::max(1.4826 * median(magnitude), 1e-3 * mean_image);
    for (size_t k = 0; k < pixels.size(); ++k) {
      const double r = residual[k] / (kCauchy * sigma);
      weight[k] = 1.0 / (1.0 + r * r);
    }
  }
  {
    // The ambient and intensity again at the direction found, the ambient no brighter than the
    // face's darkest pixels allow: on a face the ambient and a light near the camera shade alike,
    // and the free fit takes too much ambient (docs/photos.md, "The light from the shading").
    double ceiling[3] = {INFINITY, INFINITY, INFINITY};
    ambient_ceiling(pixels, true, channels, best, kAmbientQuantile, ceiling);
    Moments m[3];
    for (int c = 0; c < channels; ++c) m[c] = moments(pixels, weight, c, true);
    const Candidate bounded = evaluate(m, ceiling, channels, best.direction);
    // A ceiling that leaves no directional light at the direction found keeps the free fit.
    if (bounded.intensity[0] + bounded.intensity[1] + bounded.intensity[2] > 0) best = bounded;
    for (int c = 1; c < 3; ++c) best.ambient[c] = best.ambient[0], best.intensity[c] = best.intensity[0];
  }
  if (!grey) {
    // The light's colour: per colour the least-squares gain of the white light's rendering over
    // the weighted pixels (a grey crop says nothing of it and keeps the white light).
    DistantLight white;
    white.direction = best.direction;
    for (int c = 0; c < 3; ++c) white.ambient[c] = best.ambient[c], white.intensity[c] = best.intensity[c];
    const sh::RgbLight l = sh_light(white);
    for (int c = 0; c < 3; ++c) {
      double cross = 0, square = 0;
      for (size_t k = 0; k < pixels.size(); ++k) {
        double shade = 0;
        for (int i = 0; i < 9; ++i) shade += l[c * 9 + i] * pixels[k].transfer[i];
        const double r = pixels[k].albedo[c] * shade;
        cross += weight[k] * r * pixels[k].image[c];
        square += weight[k] * r * r;
      }
      const double gain = square > 0 ? std::clamp(cross / square, 0.1, 10.0) : 1.0;
      best.ambient[c] *= gain;
      best.intensity[c] *= gain;
    }
  }
  out.direction = best.direction;
  for (int c = 0; c < 3; ++c) {
    out.ambient[c] = best.ambient[c];
    out.intensity[c] = best.intensity[c];
  }
  out.relative_residual = mean_image > 0 ? sigma / mean_image : 0;
  out.pixels = static_cast<size_t>(std::count_if(weight.begin(), weight.end(), [](double w) { return w > 0.5; }));
  out.solved = true;
  std::vector<double> lum(pixels.size());
  for (size_t k = 0; k < pixels.size(); ++k) lum[k] = pixels[k].image[0] + pixels[k].image[1] + pixels[k].image[2];
  const double half = median(lum);
  std::nth_element(lum.begin(), lum.begin() + lum.size() * 99 / 100, lum.end());
  const double bright = lum[lum.size() * 99 / 100];
  const double from_axis = std::acos(std::clamp(out.direction[2], -1.0, 1.0)) * 180.0 / kPi;
  if (half < kDarkFace * bright)
    out.warning = "half of the face or more is in shadow (the light is at the side or behind): the light is uncertain";
  else if (from_axis > kBehindDeg)
    out.warning = "the light found comes from behind the face (" + std::to_string(static_cast<int>(from_axis)) +
                  " degrees from the camera axis): the face is mostly in shadow and the light is uncertain";
  else if (out.relative_residual > 0.5)
    out.warning = "one light explains the face's shading poorly (robust residual " +
                  std::to_string(static_cast<int>(100 * out.relative_residual)) + " % of the mean): the light is uncertain";
  return out;
}

}  // namespace facetool
