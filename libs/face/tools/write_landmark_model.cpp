// Build step: dlib's 68-point landmark model as facetool's copy (LandmarkModelCopy), checked.
//
// dlib's file stores every float in a portable variable-length form that takes about 0.6 s to
// decode at every start of facetool; the copy (share/facetool/dlib/, beside the HOG detector's)
// holds the same numbers as plain arrays. The copy is written only if the shape predictor built
// from it serialises, through dlib, to the very bytes of the source file.
#include <dlib/image_processing.h>

#include <cstdio>
#include <exception>
#include <sstream>
#include <string>

#include "core/util/file_checks.h"
#include "libs/face/landmark_model_dlib.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s LANDMARK_MODEL.dat OUT_FILE\n", argv[0]);
    return 2;
  }
  const std::string source_path = argv[1], out_path = argv[2];
  try {
    using namespace facetool;
    const std::string bytes = read_regular_input_file(source_path, kMaxWeightsFileBytes, "landmark model");
    std::istringstream in(bytes);
    const LandmarkModelCopy copy = portable::landmark_model_copy_of(in);
    std::ostringstream again;
    dlib::serialize(portable::shape_predictor_from_copy(copy), again);
    if (again.str() != bytes) {
      std::fprintf(stderr,
                   "the shape predictor rebuilt from '%s' differs from the file (%zu bytes against %zu): "
                   "no copy written; facetool reads dlib's file (slower to start)\n",
                   source_path.c_str(), again.str().size(), bytes.size());
      return 1;
    }
    const std::optional<LandmarkModelSource> source = landmark_model_source(source_path);
    check(source.has_value(), "cannot read '", source_path, "'");
    write_landmark_model_copy(out_path, copy, *source);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cannot write the landmark model copy '%s': %s\n", out_path.c_str(), e.what());
    return 1;
  }
  return 0;
}
