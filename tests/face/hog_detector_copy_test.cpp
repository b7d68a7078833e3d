// The build's decoded copy of dlib's HOG frontal face detector is found beside the program and
// holds, byte for byte, the detector dlib decodes from its built-in string; so do the bytes both
// engine copies fall back to without it (portable::builtin_hog_detector_bytes).
#include <gtest/gtest.h>

#include <dlib/image_processing/frontal_face_detector.h>

#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "libs/face/face_detector.h"
#include "libs/face/face_detector_engine.h"

namespace facetool {
namespace {

TEST(HogDetectorCopy, TheBuildsCopyIsDlibsOwnDetector) {
  const std::string path = hog_detector_copy_path();
  ASSERT_FALSE(path.empty()) << "no share/facetool/dlib/frontal_face_detector.dat beside the test";
  std::ifstream in(path, std::ios::binary);
  const std::string copy((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ostringstream dlibs;
  dlib::serialize(dlib::get_frontal_face_detector(), dlibs);
  EXPECT_GT(copy.size(), 100000u);
  EXPECT_TRUE(copy == dlibs.str()) << path << ": " << copy.size() << " bytes against dlib's "
                                   << dlibs.str().size() << " (a copy from another dlib? rebuild)";
  EXPECT_TRUE(portable::builtin_hog_detector_bytes() == copy) << "the engines' fallback bytes differ from the copy";
}

}  // namespace
}  // namespace facetool
