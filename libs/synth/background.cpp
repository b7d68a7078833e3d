// Environment views and image crops for backgrounds.
#include "libs/synth/background.h"

#include <algorithm>
#include <filesystem>

#include "libs/io/image_io.h"
#include "core/sh/sh_eval.h"
#include "core/util/error.h"

namespace facetool {
namespace fs = std::filesystem;

namespace {
bool is_image_file(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  for (const char* known : {".png", ".jpg", ".jpeg", ".exr", ".hdr", ".tif", ".tiff", ".bmp"})
    if (ext == known) return true;
  return false;
}
bool is_8bit_file(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return ext != ".exr" && ext != ".hdr";
}
}  // namespace

BackgroundSource::BackgroundSource(const std::string& image_folder) {
  if (image_folder.empty()) return;
  check(fs::is_directory(image_folder), "background folder '", image_folder,
        "' does not exist; pass --backgrounds DIR with images that contain no faces");
  for (const auto& entry : fs::directory_iterator(image_folder))
    if (entry.is_regular_file() && is_image_file(entry.path()))
      images_.push_back(entry.path().string());
  std::sort(images_.begin(), images_.end());
  check(!images_.empty(), "background folder '", image_folder,
        "' holds no images (.png, .jpg, .exr, .hdr, .tif, .bmp)");
}

void BackgroundSource::fill(Random& random, const Camera& camera, const LightSource& source,
                            const SampledLight& light, double scale,
                            std::vector<float>& rgb) const {
  const int w = camera.width, h = camera.height;
  const size_t plane = static_cast<size_t>(w) * h;
  rgb.assign(plane * 3, 0.0f);
  if (!images_.empty()) {
    const std::string& path = images_[random.index(images_.size())];
    const RgbImage image = read_rgb_image(path, is_8bit_file(path));
    const double shorter = std::min(image.width, image.height);
    const double crop = shorter * random.uniform(0.5, 1.0);
    const double crop_w = crop, crop_h = crop * h / w;
    const double x0 = random.uniform(0.0, std::max(0.0, image.width - crop_w));
    const double y0 = random.uniform(0.0, std::max(0.0, image.height - crop_h));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double sx = std::clamp(x0 + (x + 0.5) * crop_w / w - 0.5, 0.0, image.width - 1.0);
        const double sy = std::clamp(y0 + (y + 0.5) * crop_h / h - 0.5, 0.0, image.height - 1.0);
        const int ix = static_cast<int>(sx), iy = static_cast<int>(sy);
        const int jx = std::min(ix + 1, image.width - 1), jy = std::min(iy + 1, image.height - 1);
        const float tx = static_cast<float>(sx - ix), ty = static_cast<float>(sy - iy);
        for (int c = 0; c < 3; ++c) {
          const float top = image.at(ix, iy)[c] * (1 - tx) + image.at(jx, iy)[c] * tx;
          const float bottom = image.at(ix, jy)[c] * (1 - tx) + image.at(jx, jy)[c] * tx;
          rgb[c * plane + static_cast<size_t>(y) * w + x] =
              std::clamp(top * (1 - ty) + bottom * ty, 0.0f, 1.0f);
        }
      }
    return;
  }
  const Mat3f inverse = light.rotation.transposed();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Vec3f d = camera.ray_direction(x, y);
      Vec3f radiance;
      if (source.environment) {
        radiance = environment_radiance(*source.environment, inverse * d);
        for (int c = 0; c < 3; ++c) radiance[c] *= light.gain[c];
      } else {
        const auto value = sh::light_eval(light.light, {d.x, d.y, d.z});
        radiance = {static_cast<float>(value[0]), static_cast<float>(value[1]),
                    static_cast<float>(value[2])};
      }
      for (int c = 0; c < 3; ++c)
        rgb[c * plane + static_cast<size_t>(y) * w + x] =
            std::clamp(static_cast<float>(radiance[c] * scale), 0.0f, 1.0f);
    }
}

}  // namespace facetool
