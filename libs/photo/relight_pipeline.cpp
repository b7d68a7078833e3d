// Relighting decomposed photos: render every face under the new light, paste back.
#include "libs/photo/relight_pipeline.h"

#include <algorithm>

#include "libs/face/frame_rotation.h"
#include "libs/face/landmark_drawing.h"
#include "libs/light/light_preview.h"
#include "core/sh/sh_rotation.h"
#include "core/util/error.h"

namespace facetool {
namespace {

sh::Mat3 transpose(const sh::Mat3& m) {
  sh::Mat3 t{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) t[i][j] = m[j][i];
  return t;
}

}  // namespace

RelitPhoto relight_photo(const DecomposedPhoto& photo, const sh::RgbLight& light,
                         const RelightSettings& settings, RendererPlugin& renderer, Backend& backend) {
  check(settings.mode != relight::Mode::Ratio || photo.layers.made.has(PhotoLayer::kShading),
        "relighting by the ratio of shadings needs the photo's shading layer, which was not computed (the layers "
        "asked of decompose(), layers=, left it out): add 'shading' to them, or relight in 'render' mode");
  const Decomposition& d = photo.decomposition;
  const int n = d.count, s = d.size, w = photo.photo.width, h = photo.photo.height;
  const size_t plane = static_cast<size_t>(w) * h, crop_plane = static_cast<size_t>(s) * s;
  // The new light in each face's crop frame: the inverse of the crop-to-photo turn.
  std::vector<float> lights(static_cast<size_t>(n) * sh::kLightCoeffCount);
  for (int k = 0; k < n; ++k) {
    const sh::Mat3 to_crop = transpose(crop_to_photo_rotation(photo.crops[k].alignment.photo_to_crop));
    const sh::RgbLight crop_light = sh::rotate_light(light, to_crop);
    for (int i = 0; i < sh::kLightCoeffCount; ++i)
      lights[static_cast<size_t>(k) * sh::kLightCoeffCount + i] = static_cast<float>(crop_light[i]);
  }
  std::vector<float> visibility = d.visibility;
  if (!settings.visibility) {
    const sh::ShCoeffs open = relight::open_visibility();
    for (int k = 0; k < n; ++k)
      for (int i = 0; i < sh::kCoeffCount; ++i)
        std::fill_n(visibility.begin() + (static_cast<size_t>(k) * 9 + i) * crop_plane, crop_plane,
                    static_cast<float>(open[i]));
  }
  RenderInputs in{Tensor::from_host(backend, Shape{n, 3, s, s}, d.albedo),
                  Tensor::from_host(backend, Shape{n, 3, s, s}, d.normal),
                  Tensor::from_host(backend, Shape{n, 9, s, s}, visibility),
                  Tensor::from_host(backend, Shape{n, sh::kLightCoeffCount}, lights), Tensor()};
  RenderOutputs rendered;
  renderer.forward(in, rendered);
  const std::vector<float> crop_shading = rendered.shading.to_host(), crop_image = rendered.image.to_host();

  RelitPhoto out;
  out.new_shading.assign(plane * 3, 1.0f);
  std::vector<float> planar = planar_from_rgb(photo.photo);
  for (int k = 0; k < n; ++k) {
    paste_channels(photo.regions[k], crop_shading.data() + k * 3 * crop_plane, 3, out.new_shading.data(), w, h);
    if (settings.mode == relight::Mode::Render)
      paste_channels(photo.regions[k], crop_image.data() + k * 3 * crop_plane, 3, planar.data(), w, h);
  }
  if (settings.mode == relight::Mode::Ratio)
    relight::apply_ratio(planar.data(), estimated_shading(photo).data(), out.new_shading.data(), plane,
                         settings.ratio_epsilon, planar.data());
  out.image = rgb_from_planar(planar.data(), w, h);
  return out;
}

std::vector<float> estimated_shading(const DecomposedPhoto& photo) {
  const std::vector<float>& alpha = photo.layers.alpha;
  const size_t plane = alpha.size();
  std::vector<float> shading = photo.layers.shading;
  for (int c = 0; c < 3; ++c)
    for (size_t p = 0; p < plane; ++p) shading[c * plane + p] += 1.0f - alpha[p];
  return shading;
}

RgbImage shading_over_photo(const DecomposedPhoto& photo, const std::vector<float>& shading) {
  RgbImage out = photo.photo;
  const std::vector<float>& alpha = photo.layers.alpha;
  const size_t plane = alpha.size();
  for (size_t p = 0; p < plane; ++p)
    for (int c = 0; c < 3; ++c)
      out.pixels[p * 3 + c] = alpha[p] * shading[c * plane + p] + (1 - alpha[p]) * out.pixels[p * 3 + c];
  return out;
}

RgbImage side_by_side(const std::vector<RgbImage>& tiles, int height) {
  constexpr int kGap = 2;
  std::vector<RgbImage> scaled;
  int width = 0;
  for (const RgbImage& t : tiles) {
    const int tw = std::max(1, static_cast<int>(static_cast<long>(t.width) * height / std::max(1, t.height)));
    scaled.push_back(resize_to_width(t, tw));
    width += tw + (width ? kGap : 0);
  }
  RgbImage sheet;
  sheet.width = width;
  sheet.height = height;
  sheet.pixels.assign(static_cast<size_t>(width) * height * 3, 1.0f);
  int x0 = 0;
  for (const RgbImage& t : scaled) {
    for (int y = 0; y < std::min(height, t.height); ++y)
      std::copy_n(t.at(0, y), static_cast<size_t>(t.width) * 3, sheet.at(x0, y));
    x0 += t.width + kGap;
  }
  return sheet;
}

RgbImage light_sphere(const sh::RgbLight& light, int size) {
  const light::LightPreview preview = light::render_light_preview(light, size);
  RgbImage sphere;
  sphere.width = sphere.height = size;
  sphere.pixels.resize(static_cast<size_t>(size) * size * 3);
  for (int y = 0; y < size; ++y) std::copy_n(preview.image.at(0, y), static_cast<size_t>(size) * 3, sphere.at(0, y));
  return sphere;
}

void draw_light_sphere(RgbImage& image, const sh::RgbLight& light, int size) {
  size = std::min({size, image.width, image.height});
  if (size < 16) return;
  const RgbImage sphere = light_sphere(light, size);
  const int x0 = image.width - size;
  for (int y = 0; y < size; ++y) std::copy_n(sphere.at(0, y), static_cast<size_t>(size) * 3, image.at(x0, y));
}

}  // namespace facetool
