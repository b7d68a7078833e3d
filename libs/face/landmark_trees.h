// LandmarkTrees: dlib's shape predictor (ensemble of regression trees) run straight from a
// LandmarkModelCopy's arrays: dlib code, included by the detector's engine in both its
// compilations (face_detector_engine.cpp), like landmark_model_dlib.h.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "libs/face/landmark_model_copy.h"

#include <dlib/image_processing/full_object_detection.h>
#include <dlib/image_processing/shape_predictor.h>

#ifndef FACETOOL_DETECTOR_CODE
#define FACETOOL_DETECTOR_CODE portable
#endif

namespace facetool {
namespace FACETOOL_DETECTOR_CODE {

// The landmarks dlib::shape_predictor gives, bit for bit (the same pixel lookups through dlib's
// own functions, the same comparisons, the leaves added in the same order in float), evaluated
// from the copy's arrays: the trees' splits and leaves lie in one block each instead of one heap
// vector per leaf, and nothing is copied into dlib's objects (which took two thirds of loading
// the model). dlib::shape_predictor stays the reference its test compares with.
class LandmarkTrees {
 public:
  LandmarkTrees() = default;
  // `copy` must be consistent(). Each pixel's anchor (the nearest point of the mean shape) and
  // offset are derived from its point as dlib's constructor derives them.
  explicit LandmarkTrees(LandmarkModelCopy copy) : copy_(std::move(copy)) {
    initial_shape_.set_size(static_cast<long>(copy_.initial_shape.size()));
    for (size_t i = 0; i < copy_.initial_shape.size(); ++i) initial_shape_(static_cast<long>(i)) = copy_.initial_shape[i];
    anchors_.resize(copy_.cascades);
    deltas_.resize(copy_.cascades);
    for (uint32_t c = 0; c < copy_.cascades; ++c) {
      std::vector<dlib::vector<float, 2>> pixels;
      for (uint32_t p = 0; p < copy_.pixels; ++p) {
        const float* xy = &copy_.pixel_coordinates[2 * (size_t{c} * copy_.pixels + p)];
        pixels.emplace_back(xy[0], xy[1]);
      }
      dlib::impl::create_shape_relative_encoding(initial_shape_, pixels, anchors_[c], deltas_[c]);
    }
  }

  unsigned long num_parts() const { return copy_.parts; }

  // The shape in `rect` of `image` (any dlib image of grey bytes), as
  // dlib::shape_predictor::operator() gives it.
  template <typename image_type>
  dlib::full_object_detection operator()(const image_type& image, const dlib::rectangle& rect) const {
    dlib::matrix<float, 0, 1> shape = initial_shape_;
    std::vector<float> values;  // the pixels of one cascade level
    const size_t length = 2 * size_t{copy_.parts}, splits = copy_.splits;
    for (uint32_t c = 0; c < copy_.cascades; ++c) {
      dlib::impl::extract_feature_pixel_values(image, rect, shape, initial_shape_, anchors_[c], deltas_[c], values);
      float* s = &shape(0);
      for (uint32_t t = 0; t < copy_.trees; ++t) {
        const size_t tree = size_t{c} * copy_.trees + t;
        const uint32_t* compared = &copy_.split_pixels[2 * tree * splits];
        const float* thresholds = &copy_.split_thresholds[tree * splits];
        size_t i = 0;  // breadth first: node i's children are 2i + 1 (left) and 2i + 2
        while (i < splits) i = values[compared[2 * i]] - values[compared[2 * i + 1]] > thresholds[i] ? 2 * i + 1 : 2 * i + 2;
        const float* leaf = &copy_.leaf_values[(tree * (splits + 1) + (i - splits)) * length];
        for (size_t k = 0; k < length; ++k) s[k] += leaf[k];
      }
    }
    const dlib::point_transform_affine to_image = dlib::impl::unnormalizing_tform(rect);
    std::vector<dlib::point> parts(copy_.parts);
    for (uint32_t i = 0; i < copy_.parts; ++i) parts[i] = to_image(dlib::impl::location(shape, i));
    return dlib::full_object_detection(rect, parts);
  }

 private:
  LandmarkModelCopy copy_;
  dlib::matrix<float, 0, 1> initial_shape_;
  std::vector<std::vector<unsigned long>> anchors_;             // per level: each pixel's point
  std::vector<std::vector<dlib::vector<float, 2>>> deltas_;     // per level: each pixel's offset
};

}  // namespace FACETOOL_DETECTOR_CODE
}  // namespace facetool
