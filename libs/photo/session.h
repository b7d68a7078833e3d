// Session: facetool as a program would use it in a few lines: the shipped model (or given weights),
// its renderer, backend and face detector with the command line's defaults; photos in, decomposed
// photos and relit photos out.
#pragma once

#include <memory>
#include <string>

#include "core/backend/backend.h"
#include "core/plugin/plugin_loader.h"
#include "libs/face/face_detector.h"
#include "libs/inference/decomposer.h"
#include "libs/inference/model_loading.h"
#include "libs/photo/photo_pipeline.h"
#include "libs/photo/relight_pipeline.h"

namespace facetool {

// What `facetool infer` takes as options before the photos; every default is the command line's.
struct SessionOptions {
  std::string weights;                   // --model (empty: the shipped model, libs/model/default_model.h)
  std::string backend = "cpu";           // --backend
  std::string renderer = "sh_renderer";  // --renderer
  bool mirror_average = true;            // --no-mirror-average: false
  bool landmark_normals = true;          // --no-landmark-normals: false
  bool light_gain = true;                // --no-light-gain: false
  bool light_solve = true;               // --no-light-solve: false
};

// The model, its renderer and backend, and the face detector, loaded once (about a second) and
// used for any number of photos. Whatever must match the model comes from the model: the crop
// size, the framing of the crops (PhotoInferOptions::framing is set from the weights), and the
// landmark normal head. Not thread-safe: one photo at a time per Session. On the opencl backend
// a Session cannot be used in a forked child (it says so); the cpu backend can.
class Session {
 public:
  // Throws facetool::Error naming what is missing (the model, a plugin, the backend).
  explicit Session(const SessionOptions& options = {});
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // Every face of `photo` (linear RGB) decomposed as `facetool infer` does, with `options`
  // (detection, face region, paste-back; their defaults are infer's). Throws facetool::Error
  // naming `source` (or "the photo") when it holds no face. The detector is loaded on first use
  // (the landmark model named by the first call's options).
  DecomposedPhoto decompose(RgbImage photo, const std::string& source, const PhotoInferOptions& options);
  DecomposedPhoto decompose(RgbImage photo, const std::string& source = "");  // infer's default options
  // read_photo(path) (8-bit files decoded from sRGB), then decompose().
  DecomposedPhoto decompose_file(const std::string& path, const PhotoInferOptions& options);
  DecomposedPhoto decompose_file(const std::string& path);  // infer's default options
  // `photo` under `light` (photo frame, 27 coefficients): `facetool relight`'s result.
  RelitPhoto relight(const DecomposedPhoto& photo, const sh::RgbLight& light, const RelightSettings& settings = {});

  // The PhotoInferOptions decompose() uses for `options` (none: infer's defaults): the model's
  // framing put in. write_photo_files takes them too.
  PhotoInferOptions framed(const PhotoInferOptions& options) const;
  PhotoInferOptions framed() const;

  const DecompositionModel& model() const { return model_; }
  Backend& backend() { return *backend_; }
  Decomposer& decomposer() { return *decomposer_; }

 private:
  FaceDetector& detector(const PhotoInferOptions& options);
  // Throws facetool::Error in a process forked from the one that created the Session when its
  // backend does not survive fork (OpenCL: the driver's threads are not copied, so work never ends).
  void check_not_forked() const;

  Backend* backend_ = nullptr;
  PluginLoader plugins_;
  DecompositionModel model_;
  std::unique_ptr<Decomposer> decomposer_;
  std::unique_ptr<FaceDetector> detector_;
  PhotoInferOptions defaults_;  // infer's
  long creator_pid_ = 0;
};

}  // namespace facetool
