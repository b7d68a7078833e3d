// Alignment, warp and mask of one face.
#include "libs/face/face_crops.h"

#include "libs/face/face_mask.h"
#include "libs/image/border_fill.h"
#include "core/util/stage_timer.h"

namespace facetool {

FaceCrop crop_face(const RgbImage& photo, const DetectedFace& face, int crop_size,
                   bool extend_forehead, const CropFraming& framing) {
  StageTimer timer("align");
  FaceCrop c;
  c.face = face;
  c.alignment = align_face(face.landmarks, crop_size, framing);
  c.rgb = warp_to_crop(photo, c.alignment.photo_to_crop, crop_size, framing.border, &c.inside);
  c.mask_polygon = face_mask_polygon(c.alignment.crop_landmarks, extend_forehead);
  c.mask = rasterize_mask(c.mask_polygon, crop_size);
  if (framing.border == BorderFill::kRingMean) cut_mask_outside_photo(c.mask, c.inside);
  return c;
}

}  // namespace facetool
