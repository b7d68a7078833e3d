// Fitting every face of a photo and writing its products: the largest face at the photo's
// folder, face k > 0 under face_<k>/, and a contact sheet (shared by `facetool fit` and
// `facetool infer --with-fit`; docs/fit.md).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "libs/face/face_detector.h"
#include "libs/fit/fit_basis.h"
#include "libs/fit/fit_render.h"
#include "libs/fit/landmark_fit.h"
#include "libs/io/image_io.h"
#include "libs/synth/visibility.h"

namespace facetool {

struct PhotoFitOptions {
  // The products' normals are smoothed by this fraction of the eye distance unless told
  // otherwise (docs/fit.md, "Smoothed normals": measured on photo-textured renders).
  static constexpr double kDefaultNormalSmoothing = 0.025;
  PhotoFitOptions() { render.normal_smoothing = kDefaultNormalSmoothing; }
  FitSettings fit;
  FitRenderSettings render;
  int direction_count = 872;  // visibility directions, as the synthetic generator's
  bool contact_sheet = true;
};

// Where the time of one photo went (wall seconds, all faces).
struct PhotoFitTiming {
  double fit = 0, geometry = 0, visibility = 0;
  int faces = 0;
};

class PhotoFitter {
 public:
  PhotoFitter(std::shared_ptr<const FitBasis> basis, PhotoFitOptions options);

  // `faces` ordered largest first (main face first), as order_faces_by_size gives.
  std::vector<FaceFit> fit(const RgbImage& photo, const std::vector<DetectedFace>& faces) const;
  // Renders the fits and writes every face's files (the main face's in `folder`, face k's in
  // folder/face_<k>/) and contact_sheet.png; each face's set is written atomically.
  void write(const std::string& folder, const RgbImage& photo, const std::vector<DetectedFace>& faces,
             const std::vector<FaceFit>& fits, const std::string& source, PhotoFitTiming* timing = nullptr) const;

  const FitBasis& basis() const { return *basis_; }
  const PhotoFitOptions& options() const { return options_; }

 private:
  std::shared_ptr<const FitBasis> basis_;
  PhotoFitOptions options_;
  VisibilitySampler sampler_;
};

// Faces by box size, largest first.
std::vector<DetectedFace> order_faces_by_size(std::vector<DetectedFace> faces);

// One contact-sheet row: the photo with landmarks and the fitted mesh's wireframe, the normals
// ((n + 1) / 2 over the photo) and the visibility's ambient term, each `width` pixels wide.
RgbImage fit_contact_sheet_row(const RgbImage& photo, const std::vector<DetectedFace>& faces,
                               const std::vector<FaceFit>& fits, const std::vector<FitRendering>& renderings,
                               int width);

}  // namespace facetool
