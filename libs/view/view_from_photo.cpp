// A DecomposedPhoto in memory as the view page's inputs: the folder reader's ViewPhoto without the folder.
#include "libs/view/view_from_photo.h"

#include "core/util/error.h"
#include "libs/photo/photo_files.h"

namespace facetool::view {

ViewPhoto view_photo_from(const DecomposedPhoto& photo, const std::string& name, double feather, bool forehead,
                          int max_side) {
  const int w = photo.photo.width, h = photo.photo.height, s = photo.crop_size, n = photo.decomposition.count;
  check(n > 0 && photo.crops.size() == static_cast<size_t>(n), "view: the photo holds no decomposed face");
  check(n <= kMaxViewFaces, "view: the photo has ", n, " faces; the page relights at most ", kMaxViewFaces,
        " (one WebGL pass)");
  check(w >= 16 && h >= 16 && w <= max_side && h <= max_side, "view: the photo is ", w, "x", h,
        "; the page shows photos of 16 to ", max_side, " pixels a side (browsers' WebGL textures): decompose a downscaled one");
  ViewPhoto out;
  out.name = name;
  out.source = photo.path;
  out.width = w;
  out.height = h;
  out.feather = feather;
  out.mask_recorded = true;
  out.photo = photo.photo.pixels;
  out.alpha = photo.layers.alpha;
  const size_t plane = static_cast<size_t>(s) * s;
  const Decomposition& d = photo.decomposition;
  for (int k = 0; k < n; ++k) {
    const FaceCrop& crop = photo.crops[k];
    ViewFace face;
    face.folder = "face_" + std::to_string(k);  // as infer names it
    face.crop_size = s;
    face.photo_to_crop = crop.alignment.photo_to_crop;
    face.landmarks.assign(crop.face.landmarks.begin(), crop.face.landmarks.end());
    face.box = {crop.face.left, crop.face.top, crop.face.right, crop.face.bottom};
    face.photo_light = photo.photo_lights[k];
    // face_K/{normal,visibility,albedo,shading}.exr's channels, in the folder reader's order.
    for (const auto& [planes, channels] : {std::pair{&d.normal, 3}, {&d.visibility, 9}, {&d.albedo, 3}, {&d.shading, 3}}) {
      const float* first = planes->data() + static_cast<size_t>(k) * channels * plane;
      face.planes.insert(face.planes.end(), first, first + channels * plane);
    }
    out.faces.push_back(std::move(face));
  }
  set_face_geometry(out, forehead);
  out.mask_mismatch = mask_mismatch(out, forehead);
  for (const std::string& layer : view_layer_names()) out.layer_pngs.push_back({layer, encode_photo_layer_png(photo, layer)});
  return out;
}

}  // namespace facetool::view
