// Session: the shipped model, renderer, backend and detector with the command line's defaults.
#include "libs/photo/session.h"

#include <unistd.h>

#include <filesystem>
#include <utility>

#include "core/backend/registry.h"
#include "core/util/memory_budget.h"
#include "libs/face/photo_reader.h"
#include "libs/model/default_model.h"

namespace facetool {

Session::Session(const SessionOptions& options) {
  backend_ = &get_backend(options.backend);
  plugins_.set_search_dirs(library_plugin_dirs());
  plugins_.discover();
  const std::string weights = options.weights.empty() ? default_model_path() : options.weights;
  std::error_code size_error;
  const uintmax_t size = std::filesystem::file_size(weights, size_error);
  // The file read whole, then the network's tensors and its workspace: about 4 times the file.
  model_ = naming_out_of_memory("loading the model '" + weights + "'", size_error ? 0 : 4 * size + (64u << 20),
                                [&] { return load_decomposition_model(plugins_, *backend_, weights, options.renderer); });
  decomposer_ = std::make_unique<Decomposer>(*model_.network, *model_.renderer);
  decomposer_->set_landmark_normals(options.landmark_normals ? model_.landmark_normals.get() : nullptr);
  decomposer_->set_mirror_average(options.mirror_average);
  decomposer_->set_light_gain(options.light_gain);
  decomposer_->set_light_solve(options.light_solve);
  creator_pid_ = static_cast<long>(::getpid());
}

Session::~Session() = default;

void Session::check_not_forked() const {
  const long pid = static_cast<long>(::getpid());
  check(pid == creator_pid_ || backend_->name() == "cpu", "the ", backend_->name(), " backend was started in process ",
        creator_pid_, " and this process (", pid, ") is a fork of it, where ", backend_->name(),
        " cannot run (its driver's threads are not copied by fork): load the model in this process, or start "
        "worker processes with the 'spawn' or 'forkserver' method (Python's multiprocessing)");
}

PhotoInferOptions Session::framed(const PhotoInferOptions& options) const {
  PhotoInferOptions framed = options;
  framed.framing = model_.framing;  // crops framed as the model was trained
  return framed;
}

PhotoInferOptions Session::framed() const { return framed(defaults_); }

FaceDetector& Session::detector(const PhotoInferOptions& options) {
  if (!detector_) detector_ = make_face_detector(options);
  return *detector_;
}

DecomposedPhoto Session::decompose(RgbImage photo, const std::string& source, const PhotoInferOptions& options) {
  check_not_forked();
  const PhotoInferOptions o = framed(options);
  PhotoDecomposer photos(detector(o), *decomposer_, *backend_, model_.input_size, o);
  return photos.decompose(std::move(photo), source);
}

DecomposedPhoto Session::decompose(RgbImage photo, const std::string& source) {
  return decompose(std::move(photo), source, defaults_);
}

DecomposedPhoto Session::decompose_file(const std::string& path) { return decompose_file(path, defaults_); }

DecomposedPhoto Session::decompose_file(const std::string& path, const PhotoInferOptions& options) {
  check_not_forked();
  const PhotoInferOptions o = framed(options);
  PhotoDecomposer photos(detector(o), *decomposer_, *backend_, model_.input_size, o);
  return photos.decompose_file(path);
}

RelitPhoto Session::relight(const DecomposedPhoto& photo, const sh::RgbLight& light, const RelightSettings& settings) {
  check_not_forked();
  check(photo.crop_size == model_.input_size, "this photo was decomposed by a model of ", photo.crop_size,
        "-pixel crops; relight it with that model");
  return relight_photo(photo, light, settings, *model_.renderer, *backend_);
}

}  // namespace facetool
