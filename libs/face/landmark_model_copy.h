// LandmarkModelCopy: dlib's 68-point shape predictor as plain arrays, and facetool's file of them
// (mapped at start, not read; dlib's own file takes 0.65 s to parse; landmark_trees.h runs it).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace facetool {

// An ensemble-of-regression-trees shape predictor (dlib::shape_predictor) with full trees of
// one depth: `cascades` levels of `trees` trees, each with `splits` split nodes (breadth first)
// and splits + 1 leaves of 2 x `parts` values. The pixels each level compares are given as
// points of the mean shape's frame (dlib recomputes their anchors and offsets from them).
struct LandmarkModelCopy {
  uint32_t parts = 0, cascades = 0, trees = 0, splits = 0, pixels = 0;
  std::vector<float> initial_shape;      // 2 x parts: x0 y0 x1 y1 ...
  std::vector<float> pixel_coordinates;  // cascades x pixels x 2
  std::vector<uint32_t> split_pixels;    // cascades x trees x splits x 2: the two pixels compared
  std::vector<float> split_thresholds;   // cascades x trees x splits
  std::vector<float> leaf_values;        // cascades x trees x (splits + 1) x 2 parts

  uint32_t leaves() const { return splits + 1; }
  // Sizes consistent, split pixels in range, leaves a power of two (dlib's requirement).
  bool consistent() const;
};

// The arrays of a landmark model wherever they lie: a LandmarkModelCopy's vectors or a mapped copy
// file (MappedLandmarkModel); sizes as in LandmarkModelCopy.
struct LandmarkModelArrays {
  uint32_t parts = 0, cascades = 0, trees = 0, splits = 0, pixels = 0;
  const float* initial_shape = nullptr;
  const float* pixel_coordinates = nullptr;
  const uint32_t* split_pixels = nullptr;
  const float* split_thresholds = nullptr;
  const float* leaf_values = nullptr;
};
LandmarkModelArrays arrays_of(const LandmarkModelCopy& copy);

// A copy's file mapped read-only and checked: its arrays are the page cache's own pages, nothing
// copied into the process (a start reads 67 MB less). Move-only; unmapped when destroyed.
class MappedLandmarkModel {
 public:
  MappedLandmarkModel(MappedLandmarkModel&& other) noexcept;
  MappedLandmarkModel& operator=(MappedLandmarkModel&& other) noexcept;
  MappedLandmarkModel(const MappedLandmarkModel&) = delete;
  MappedLandmarkModel& operator=(const MappedLandmarkModel&) = delete;
  ~MappedLandmarkModel();
  const LandmarkModelArrays& arrays() const { return arrays_; }

 private:
  friend std::optional<MappedLandmarkModel> map_landmark_model_copy(const std::string& path,
                                                                    const std::string& source_path);
  MappedLandmarkModel() = default;
  void* base_ = nullptr;
  size_t bytes_ = 0;
  LandmarkModelArrays arrays_;
};

// Which file a copy was made from, so that a copy is only ever used for that file unchanged.
struct LandmarkModelSource {
  std::string path;  // as given to the build step
  uint64_t size = 0;
  int64_t modified_ns = 0;  // last modification, nanoseconds since the epoch
  bool operator==(const LandmarkModelSource& o) const {
    return path == o.path && size == o.size && modified_ns == o.modified_ns;
  }
};

// The source's identity from the file system; nullopt when it cannot be read.
std::optional<LandmarkModelSource> landmark_model_source(const std::string& path);

// Writes `copy` of `source` to `path` atomically (temporary name, then rename); throws
// facetool::Error naming the file on failure.
void write_landmark_model_copy(const std::string& path, const LandmarkModelCopy& copy,
                               const LandmarkModelSource& source);

// Maps the copy at `path` if it was made from the file `source_path` names (the same file, any
// spelling) as that file is now (size and modification time), and is intact (layout, sizes and
// checksum); nullopt otherwise, and the caller reads dlib's file instead.
std::optional<MappedLandmarkModel> map_landmark_model_copy(const std::string& path, const std::string& source_path);
// The same checks, the arrays copied out of the file.
std::optional<LandmarkModelCopy> read_landmark_model_copy(const std::string& path, const std::string& source_path);

}  // namespace facetool
