// `infer --aligned` inputs: aligned by their landmarks when a face is found, else stretched.
#include "apps/facetool/infer/aligned_input.h"

#include "apps/facetool/commands/component_images.h"
#include "libs/face/face_crops.h"
#include "libs/image/resize.h"

namespace facetool {

AlignedInput read_aligned_input(const std::string& path, int size, FaceDetector* detector,
                                const PhotoInferOptions& options) {
  const RgbImage image = read_crop_image(path);
  AlignedInput input;
  if (detector) {
    DetectionOptions one = options.detection;
    one.max_faces = 1;
    const std::vector<DetectedFace> faces = detector->detect(image, one);
    if (!faces.empty()) {
      input.crop = crop_face(image, faces[0], size, options.extends_forehead(), options.framing);
      input.by_landmarks = true;
      return input;
    }
    input.reason = no_face_reason(image, one);
  }
  input.crop.rgb = resize_planar(planar_from_rgb(image), 3, image.width, image.height, size, size);
  return input;
}

}  // namespace facetool
