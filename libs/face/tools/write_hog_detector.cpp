// Build step: dlib's frontal face detector, decoded once and written in dlib's serialized form.
//
// dlib::get_frontal_face_detector() decodes the detector from a compressed string compiled into
// dlib, which takes about 0.3 s at every start of facetool; the serialized copy this writes
// (share/facetool/dlib/frontal_face_detector.dat) reads in a few milliseconds.
#include <dlib/image_processing/frontal_face_detector.h>

#include <cstdio>
#include <exception>
#include <fstream>
#include <string>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT_FILE\n", argv[0]);
    return 2;
  }
  // Under a temporary name, renamed last: an interrupted build never leaves a partial file under
  // the name facetool reads (which would then fall back to decoding dlib's copy anyway).
  const std::string final_path = argv[1], temporary = final_path + ".tmp";
  try {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    dlib::serialize(dlib::get_frontal_face_detector(), out);
    out.close();
    if (!out) {
      std::fprintf(stderr, "cannot write '%s' (a full disk?)\n", temporary.c_str());
      std::remove(temporary.c_str());
      return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cannot write '%s': %s\n", temporary.c_str(), e.what());
    std::remove(temporary.c_str());
    return 1;
  }
  if (std::rename(temporary.c_str(), final_path.c_str()) != 0) {
    std::fprintf(stderr, "cannot rename '%s' to '%s'\n", temporary.c_str(), final_path.c_str());
    std::remove(temporary.c_str());
    return 1;
  }
  return 0;
}
