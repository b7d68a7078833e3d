// The files of one fitted face: normal.exr, depth.exr, visibility.exr, mask.png, mesh.obj with
// mesh.mtl and texture.png (the photo through projected UVs), fit.json (docs/fit.md).
#pragma once

#include <string>
#include <vector>

#include "libs/face/face_detector.h"
#include "libs/fit/fit_basis.h"
#include "libs/fit/fit_render.h"
#include "libs/fit/landmark_fit.h"
#include "libs/io/image_io.h"
#include "core/util/atomic_file.h"

namespace facetool {

// fit.json: the photo, the detection, the camera (model, principal point, focal length or
// scale), the pose (angle-axis, roll/pitch/yaw, translation), the identity and named expression
// weights, the landmark residual and the fit's timing.
std::string fit_json(const FitBasis& basis, const FaceFit& fit, const DetectedFace& face,
                     const std::string& source);

// The Wavefront OBJ text of the fitted mesh (camera frame) with texture coordinates projecting
// each vertex into the photo, using material file `mtl_name`.
std::string fitted_mesh_obj(const FaceFit& fit, const FaceMesh& mesh, const std::string& mtl_name);

// The contents of every file of one face in `folder` (written together by the caller with
// write_files_atomically, so a full disk leaves no half-written set). `texture` is the photo.
std::vector<FileContents> fit_product_files(const std::string& folder, const FitBasis& basis,
                                            const FaceFit& fit, const FitRendering& rendering,
                                            const DetectedFace& face, const RgbImage& texture,
                                            const std::string& source);

}  // namespace facetool
