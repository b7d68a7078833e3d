// `facetool infer` on whole photos: detection, alignment, the network on each face's crop, and
// everything pasted back at the photo's resolution (docs/photos.md).
#pragma once

#include <boost/program_options.hpp>
#include <string>
#include <vector>

#include "apps/facetool/commands/command_options.h"
#include "core/backend/backend.h"
#include "core/face/face_detector.h"
#include "core/inference/decomposer.h"

namespace facetool {

class PhotoFitter;

struct PhotoInferOptions {
  DetectionOptions detection;
  std::string landmark_model = kDefaultLandmarkModel;
  bool extend_forehead = false;  // --forehead
  double feather = 3.0;          // --feather, crop pixels
  bool transparent = false;      // --transparent: PNGs transparent outside the faces
  bool contact_sheet = true;
  int batch = 8;
  const PhotoFitter* with_fit = nullptr;  // --with-fit: the landmark fit too, in <photo folder>/fit/
};

// The photo options of `infer` (also used by prepare-real for the detection ones).
void add_photo_detection_options(boost::program_options::options_description& options);
void add_photo_infer_options(boost::program_options::options_description& options);
// Valid ranges of the detection and paste-back options (for check_option_ranges).
std::vector<OptionRange> photo_option_ranges();
PhotoInferOptions photo_options_from(const boost::program_options::variables_map& values);

// PHOTO|DIR arguments as photo files: a folder gives its image files (by extension, sorted, not
// recursive). Throws facetool::Error for a path that is neither.
std::vector<std::string> expand_photo_inputs(const std::vector<std::string>& inputs);

// Runs the decomposer over `count` planar crops [count][3][size][size] in batches of `batch`
// and concatenates the results (also used by `facetool relight`).
Decomposition decompose_all(Decomposer& decomposer, Backend& backend, const std::vector<float>& crops,
                            int count, int size, int batch);

// Planar [3][w*h] values as an interleaved RgbImage.
RgbImage planar_rgb(const float* planar, int w, int h);

// Runs every photo; a photo that cannot be read or has no face gets a line on stderr and the
// run goes on. Returns the number of such photos.
int infer_photos(const std::vector<std::string>& photos, const std::string& out_dir,
                 Decomposer& decomposer, Backend& backend, int crop_size,
                 const PhotoInferOptions& options);

}  // namespace facetool
