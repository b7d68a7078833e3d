// dlib's shape predictor to and from LandmarkModelCopy: dlib code, included by the detector's
// engine (in both its compilations, among dlib's headers: face_detector_engine.cpp), by the build
// step that writes the copy (tools/write_landmark_model.cpp) and by its test.
#pragma once

#include <algorithm>
#include <cstdint>
#include <istream>
#include <vector>

#include "core/util/error.h"
#include "libs/face/landmark_model_copy.h"

#include <dlib/image_processing/shape_predictor.h>
#include <dlib/serialize.h>

#include "libs/face/detector_code.h"

namespace facetool {
namespace FACETOOL_DETECTOR_CODE {

// dlib's serialised shape predictor (the content of shape_predictor_68_face_landmarks.dat) as a
// copy: dlib's own parsers read its parts in the order dlib::deserialize(shape_predictor&) does;
// each pixel is stored as its anchor point of the mean shape plus its offset, the form dlib's
// public constructor takes. Throws dlib::serialization_error or facetool::Error when the stream
// holds something else (another version, trees of different depths).
inline LandmarkModelCopy landmark_model_copy_of(std::istream& in) {
  int version = 0;
  dlib::matrix<float, 0, 1> initial_shape;
  std::vector<std::vector<dlib::impl::regression_tree>> forests;
  std::vector<std::vector<unsigned long>> anchors;
  std::vector<std::vector<dlib::vector<float, 2>>> deltas;
  dlib::deserialize(version, in);
  check(version == 1, "dlib shape predictor of version ", version, " (facetool knows version 1)");
  dlib::deserialize(initial_shape, in);
  dlib::deserialize(forests, in);
  dlib::deserialize(anchors, in);
  dlib::deserialize(deltas, in);
  check(!forests.empty() && !forests[0].empty() && anchors.size() == forests.size() &&
            deltas.size() == forests.size() && initial_shape.size() % 2 == 0 && initial_shape.size() > 0,
        "dlib shape predictor with an unexpected layout");
  LandmarkModelCopy copy;
  copy.parts = static_cast<uint32_t>(initial_shape.size() / 2);
  copy.cascades = static_cast<uint32_t>(forests.size());
  copy.trees = static_cast<uint32_t>(forests[0].size());
  copy.splits = static_cast<uint32_t>(forests[0][0].splits.size());
  copy.pixels = static_cast<uint32_t>(anchors[0].size());
  copy.initial_shape.assign(initial_shape.begin(), initial_shape.end());
  for (size_t c = 0; c < forests.size(); ++c) {
    check(forests[c].size() == copy.trees && anchors[c].size() == copy.pixels && deltas[c].size() == copy.pixels,
          "dlib shape predictor whose cascade levels differ in size");
    for (size_t p = 0; p < copy.pixels; ++p) {
      check(anchors[c][p] < copy.parts, "dlib shape predictor with an anchor out of range");
      const dlib::vector<float, 2> pixel = dlib::impl::location(initial_shape, anchors[c][p]) + deltas[c][p];
      copy.pixel_coordinates.push_back(pixel.x());
      copy.pixel_coordinates.push_back(pixel.y());
    }
    for (const dlib::impl::regression_tree& tree : forests[c]) {
      check(tree.splits.size() == copy.splits && tree.leaf_values.size() == copy.leaves(),
            "dlib shape predictor whose trees differ in depth");
      for (const dlib::impl::split_feature& split : tree.splits) {
        copy.split_pixels.push_back(static_cast<uint32_t>(split.idx1));
        copy.split_pixels.push_back(static_cast<uint32_t>(split.idx2));
        copy.split_thresholds.push_back(split.thresh);
      }
      for (const dlib::matrix<float, 0, 1>& leaf : tree.leaf_values) {
        check(leaf.size() == 2 * copy.parts, "dlib shape predictor with leaves of the wrong length");
        copy.leaf_values.insert(copy.leaf_values.end(), leaf.begin(), leaf.end());
      }
    }
  }
  check(copy.consistent(), "dlib shape predictor with an unexpected layout");
  return copy;
}

// The shape predictor a copy holds, built through dlib's public constructor (which derives each
// pixel's anchor and offset from its point again); `copy` must be consistent().
inline dlib::shape_predictor shape_predictor_from_copy(const LandmarkModelCopy& copy) {
  dlib::matrix<float, 0, 1> initial_shape(copy.initial_shape.size());
  for (size_t i = 0; i < copy.initial_shape.size(); ++i) initial_shape(i) = copy.initial_shape[i];
  std::vector<std::vector<dlib::impl::regression_tree>> forests(copy.cascades);
  std::vector<std::vector<dlib::vector<float, 2>>> pixels(copy.cascades);
  const size_t leaf_length = 2 * size_t{copy.parts};
  size_t tree_index = 0;
  for (uint32_t c = 0; c < copy.cascades; ++c) {
    for (uint32_t p = 0; p < copy.pixels; ++p) {
      const float* xy = &copy.pixel_coordinates[2 * (size_t{c} * copy.pixels + p)];
      pixels[c].emplace_back(xy[0], xy[1]);
    }
    forests[c].resize(copy.trees);
    for (dlib::impl::regression_tree& tree : forests[c]) {
      tree.splits.resize(copy.splits);
      for (uint32_t s = 0; s < copy.splits; ++s) {
        const size_t k = tree_index * copy.splits + s;
        tree.splits[s].idx1 = copy.split_pixels[2 * k];
        tree.splits[s].idx2 = copy.split_pixels[2 * k + 1];
        tree.splits[s].thresh = copy.split_thresholds[k];
      }
      tree.leaf_values.resize(copy.leaves());
      for (uint32_t l = 0; l < copy.leaves(); ++l) {
        const float* values = &copy.leaf_values[(tree_index * copy.leaves() + l) * leaf_length];
        tree.leaf_values[l].set_size(static_cast<long>(leaf_length));
        std::copy(values, values + leaf_length, tree.leaf_values[l].begin());
      }
      ++tree_index;
    }
  }
  return dlib::shape_predictor(initial_shape, forests, pixels);
}

}  // namespace FACETOOL_DETECTOR_CODE
}  // namespace facetool
