// Helpers for the synth tests: the ../shared assets (or a skip), scratch folders, test meshes.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "libs/synth/face_mesh.h"

namespace facetool::testing {

// ../shared relative to the source tree (a CMake define); empty when it is not there.
std::string shared_dir();
std::string ict_face_model_dir();  // shared/assets/ict-facekit/FaceXModel or ""
std::string hdri_dir();            // shared/assets/hdri or ""

// A fresh empty folder under the system temp folder, removed by the destructor.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name);
  ~ScratchDir();
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

// A UV sphere of radius 1 at the origin (counter-clockwise seen from outside).
FaceMesh make_sphere(int rings, int segments);
// Writes a text file.
void write_text(const std::string& path, const std::string& text);

}  // namespace facetool::testing

// Skips the test, saying what is missing, unless the shared asset folder `dir` exists.
#define FACETOOL_REQUIRE_SHARED(dir)                                                         \
  do {                                                                                      \
    if ((dir).empty())                                                                      \
      GTEST_SKIP() << "needs ../shared (ICT Face Model and HDRIs) beside the source tree; " \
                      "not found at " FACETOOL_SHARED_DIR;                                  \
  } while (0)
