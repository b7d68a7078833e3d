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

constexpr int kMaxViewFaces = 12;  // faces a page relights: texture units of one WebGL2 pass

// mask and feather: for folders whose faces.json does not record infer's --face-region and
// --feather (older runs); a faces.json that records them is read as it says.
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
  bool mask_recorded = false;  // the mask and feather as faces.json records them (else guessed or given)
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

// The faces' paste-back geometry from their landmarks and transforms: `forehead` the mask shape
// (infer's --face-region), photo.feather the ramp. Sets each face's region, mask_lines and the
// turn of a light into its crop's frame; the folder reader and view_photo_from share it.
void set_face_geometry(ViewPhoto& photo, bool forehead);

// The largest difference between photo.alpha and the coverage the faces' masks (`forehead` the
// shape, photo.feather the ramp) paste: 0 when the page's mask is infer's.
double mask_mismatch(const ViewPhoto& photo, bool forehead);

// Reads `folder` (one photo's folder of an infer run). Throws facetool::Error naming the folder
// or file and what to do when it is not an infer output, a file is missing or damaged, or the
// photo is larger than options.max_side.
ViewPhoto read_view_photo(const std::string& folder, const ViewOptions& options);

}  // namespace facetool::view
