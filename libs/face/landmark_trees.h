// LandmarkTrees: dlib's shape predictor (ensemble of regression trees) run straight from a
// landmark model's arrays (read or mapped: landmark_model_copy.h): dlib code, included by the
// detector's engine in both its compilations (face_detector_engine.cpp), like landmark_model_dlib.h.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "libs/face/landmark_model_copy.h"

#include <dlib/image_processing/full_object_detection.h>
#include <dlib/image_processing/shape_predictor.h>

#include "libs/face/detector_code.h"

namespace facetool {
namespace FACETOOL_DETECTOR_CODE {

// The landmarks dlib::shape_predictor gives, bit for bit (the same pixel lookups through dlib's
// own functions, the same comparisons, the leaves added in the same order in float), evaluated
// from the model's arrays: the trees' splits and leaves lie in one block each instead of one heap
// vector per leaf, and nothing is copied into dlib's objects (which took two thirds of loading
// the model); a mapped copy file is not even read into the process. dlib::shape_predictor stays
// the reference its test compares with.
class LandmarkTrees {
 public:
  LandmarkTrees() = default;
  // The model in `copy` (consistent()), or in a mapped copy file (shared by the trees' copies).
  // Each pixel's anchor (the nearest point of the mean shape) and offset are derived from its
  // point as dlib's constructor derives them.
  explicit LandmarkTrees(LandmarkModelCopy copy) : owned_(std::move(copy)) { encode_pixels(); }
  explicit LandmarkTrees(MappedLandmarkModel mapped)
      : mapped_(std::make_shared<const MappedLandmarkModel>(std::move(mapped))) {
    encode_pixels();
  }

  unsigned long num_parts() const { return arrays().parts; }

  // The shape in `rect` of `image` (any dlib image of grey bytes), as
  // dlib::shape_predictor::operator() gives it.
  template <typename image_type>
  dlib::full_object_detection operator()(const image_type& image, const dlib::rectangle& rect) const {
    const LandmarkModelArrays m = arrays();
    dlib::matrix<float, 0, 1> shape = initial_shape_;
    std::vector<float> values;  // the pixels of one cascade level
    const size_t length = 2 * size_t{m.parts}, splits = m.splits;
    for (uint32_t c = 0; c < m.cascades; ++c) {
      dlib::impl::extract_feature_pixel_values(image, rect, shape, initial_shape_, anchors_[c], deltas_[c], values);
      float* s = &shape(0);
      for (uint32_t t = 0; t < m.trees; ++t) {
        const size_t tree = size_t{c} * m.trees + t;
        const uint32_t* compared = m.split_pixels + 2 * tree * splits;
        const float* thresholds = m.split_thresholds + tree * splits;
        size_t i = 0;  // breadth first: node i's children are 2i + 1 (left) and 2i + 2
        while (i < splits) i = values[compared[2 * i]] - values[compared[2 * i + 1]] > thresholds[i] ? 2 * i + 1 : 2 * i + 2;
        const float* leaf = m.leaf_values + (tree * (splits + 1) + (i - splits)) * length;
        for (size_t k = 0; k < length; ++k) s[k] += leaf[k];
      }
    }
    const dlib::point_transform_affine to_image = dlib::impl::unnormalizing_tform(rect);
    std::vector<dlib::point> parts(m.parts);
    for (uint32_t i = 0; i < m.parts; ++i) parts[i] = to_image(dlib::impl::location(shape, i));
    return dlib::full_object_detection(rect, parts);
  }

 private:
  LandmarkModelArrays arrays() const { return mapped_ ? mapped_->arrays() : arrays_of(owned_); }

  void encode_pixels() {
    const LandmarkModelArrays m = arrays();
    initial_shape_.set_size(2 * static_cast<long>(m.parts));
    for (long i = 0; i < initial_shape_.size(); ++i) initial_shape_(i) = m.initial_shape[i];
    anchors_.resize(m.cascades);
    deltas_.resize(m.cascades);
    for (uint32_t c = 0; c < m.cascades; ++c) {
      std::vector<dlib::vector<float, 2>> pixels;
      for (uint32_t p = 0; p < m.pixels; ++p) {
        const float* xy = m.pixel_coordinates + 2 * (size_t{c} * m.pixels + p);
        pixels.emplace_back(xy[0], xy[1]);
      }
      dlib::impl::create_shape_relative_encoding(initial_shape_, pixels, anchors_[c], deltas_[c]);
    }
  }

  LandmarkModelCopy owned_;                                  // the model, when read into memory
  std::shared_ptr<const MappedLandmarkModel> mapped_;        // or the model's mapped file
  dlib::matrix<float, 0, 1> initial_shape_;
  std::vector<std::vector<unsigned long>> anchors_;          // per level: each pixel's point
  std::vector<std::vector<dlib::vector<float, 2>>> deltas_;  // per level: each pixel's offset
};

}  // namespace FACETOOL_DETECTOR_CODE
}  // namespace facetool
