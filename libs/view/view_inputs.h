// What a page of `facetool view` shows, read back from one photo's `facetool infer` folder.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/sh/sh_types.h"
#include "libs/image/similarity_transform.h"

namespace facetool::view {

// How the page's paste-back mask is made: as infer's --face-region (kAuto: whichever of the hull
// and the forehead hull reproduces the coverage stored in photo.exr).
enum class MaskShape { kAuto, kHull, kForehead };

struct ViewOptions {
  MaskShape mask = MaskShape::kAuto;
  double feather = 3.0;  // infer's --feather, crop pixels
  int max_side = 4096;   // larger photos are refused (browsers' WebGL texture sizes)
};

// One face: where its crop lies in the photo, its paste-back mask and the crop-level layers
// relight renders from (crop frame, crop_size x crop_size, planar).
struct ViewFace {
  std::string folder;  // "face_0"
  int crop_size = 0;
  Similarity2 photo_to_crop;
  std::vector<Point2> landmarks;            // photo pixels
  std::array<double, 4> box{};              // x0, y0, x1, y1 in photo pixels
  std::array<int, 4> region{};              // x0, y0, width, height: the photo pixels it pastes into
  std::vector<std::array<double, 3>> mask_lines;  // the mask's edges in crop pixels: nx x + ny y + c > 0 inside
  sh::RgbLight photo_light{};               // the estimated light, photo frame
  std::array<double, 81> photo_to_crop_sh{};  // 9x9 row-major: a light's coefficients, photo frame to crop frame
  // Planar [18][S*S]: normal x, y, z; visibility 0..8; albedo r, g, b; shading r, g, b.
  std::vector<float> planes;
};

// One decomposed photo as the page needs it.
struct ViewPhoto {
  std::string name;       // the folder's name
  std::string source;     // the photo infer read (faces.json "source")
  int width = 0, height = 0;
  double feather = 3.0;
  std::string mask_shape;  // "hull" or "forehead", as used
  double mask_mismatch = 0;  // largest difference of the page's coverage to photo.exr's
  std::vector<float> photo;  // linear RGB, interleaved
  std::vector<float> alpha;  // face coverage
  // The display layers as the PNG files infer wrote (name, bytes): albedo, normal, shading,
  // visibility, reconstruction.
  std::vector<std::pair<std::string, std::vector<unsigned char>>> layer_pngs;
  std::vector<ViewFace> faces;
};

// The layers the page shows from infer's PNGs, in the order of the page's menu.
const std::vector<std::string>& view_layer_names();

// Reads `folder` (one photo's folder of an infer run). Throws facetool::Error naming the folder
// or file and what to do when it is not an infer output, a file is missing or damaged, or the
// photo is larger than options.max_side.
ViewPhoto read_view_photo(const std::string& folder, const ViewOptions& options);

}  // namespace facetool::view
