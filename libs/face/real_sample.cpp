// Real samples: EXR layout, header check for resuming, edge test.
#include "libs/face/real_sample.h"

#include "libs/face/face_mask.h"

#include <cstdio>

#include "libs/io/exr_io.h"
#include "core/util/error.h"

namespace facetool {

namespace {
std::string number(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}
}  // namespace

LayeredImage real_sample_image(const FaceCrop& crop, const std::string& source, bool forehead,
                               const CropFraming& framing) {
  const int s = crop.alignment.crop_size;
  LayeredImage image(s, s, {"R", "G", "B", "mask"});
  const size_t plane = image.plane_size();
  std::copy(crop.rgb.begin(), crop.rgb.end(), image.pixels.begin());
  std::copy(crop.mask.begin(), crop.mask.end(), image.pixels.begin() + 3 * plane);
  std::string landmarks, transform;
  for (const Point2& p : crop.alignment.crop_landmarks)
    landmarks += (landmarks.empty() ? "" : " ") + number(p.x) + " " + number(p.y);
  const Similarity2& t = crop.alignment.photo_to_crop;
  for (double v : {t.a, -t.b, t.tx, t.b, t.a, t.ty}) transform += (transform.empty() ? "" : " ") + number(v);
  image.set_metadata("facetool:generator_version", kRealSampleVersion);
  image.set_metadata("facetool:source", source);
  image.set_metadata("facetool:landmarks", landmarks);
  image.set_metadata("facetool:transform", transform);
  image.set_metadata("facetool:detection_score", number(crop.face.score));
  image.set_metadata("facetool:mask_kind", forehead ? "landmark-hull+forehead" : "landmark-hull");
  if (framing != CropFraming{}) image.set_metadata("facetool:framing", framing_text(framing));
  return image;
}

std::string read_real_sample_source(const std::string& path) {
  try {
    const LayeredImage header = read_exr_header(path, "facetool:");
    const std::string* version = header.find_metadata("facetool:generator_version");
    const std::string* source = header.find_metadata("facetool:source");
    if (!version || *version != kRealSampleVersion || !source) return "";
    return *source;
  } catch (const Error&) {
    return "";
  }
}

double mask_fraction_outside_photo(const FaceCrop& crop, int w, int h) {
  const int s = crop.alignment.crop_size;
  const Similarity2 back = crop.alignment.photo_to_crop.inverse();
  // The whole polygon's mask (crop.mask is already cut at the photo's edge with the ring-mean fill).
  const std::vector<float> mask = rasterize_mask(crop.mask_polygon, s);
  int inside = 0, outside = 0;
  for (int y = 0; y < s; ++y)
    for (int x = 0; x < s; ++x) {
      if (mask[static_cast<size_t>(y) * s + x] <= 0) continue;
      const Point2 p = back.apply({static_cast<double>(x), static_cast<double>(y)});
      const bool out = p.x < -0.5 || p.y < -0.5 || p.x > w - 0.5 || p.y > h - 0.5;
      (out ? outside : inside) += 1;
    }
  return inside + outside > 0 ? static_cast<double>(outside) / (inside + outside) : 1.0;
}

}  // namespace facetool
