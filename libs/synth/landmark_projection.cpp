// The face model's landmark vertices through the synthetic camera (the canonical template's source).
#include "libs/synth/landmark_projection.h"

#include "libs/synth/face_model.h"
#include "libs/synth/pose_camera.h"
#include "core/util/error.h"

namespace facetool {

std::vector<std::array<double, 2>> project_neutral_landmarks(const std::string& face_model_directory,
                                                             double fov_deg, const CropFraming& framing) {
  const FaceModel model = FaceModel::load(face_model_directory);
  check(model.landmarks().size() == 68, "face model '",
        face_model_directory, "' has no 68 landmark vertices (vertex_indices.json missing?)");
  FaceMesh mesh = model.neutral();
  apply_pose(mesh, HeadPose{});
  Camera camera;
  camera.width = camera.height = 1;  // crop units: the projection is independent of the size
  camera.horizontal_fov_deg = fov_deg;
  camera.framing = framing;
  std::vector<std::array<double, 2>> out(68);
  for (int i = 0; i < 68; ++i) {
    const int32_t v = model.landmarks()[i];
    check(v >= 0, "face model '", face_model_directory, "': landmark ", i, " is not on a kept vertex");
    const std::array<double, 2> pixel = camera.project(mesh.positions[v]);
    out[i] = {pixel[0] + 0.5, pixel[1] + 0.5};  // a 1-pixel image: crop units
  }
  return out;
}

}  // namespace facetool
