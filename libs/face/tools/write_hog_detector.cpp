// Build step: dlib's frontal face detector, decoded once and written in dlib's serialized form.
//
// dlib::get_frontal_face_detector() decodes the detector from a compressed string compiled into
// dlib, which takes about 0.3 s at every start of facetool; the serialized copy this writes
// (share/facetool/dlib/frontal_face_detector.dat) reads in a few milliseconds.
#include <dlib/image_processing/frontal_face_detector.h>

#include <cstdio>
#include <exception>
#include <fstream>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT_FILE\n", argv[0]);
    return 2;
  }
  try {
    std::ofstream out(argv[1], std::ios::binary | std::ios::trunc);
    dlib::serialize(dlib::get_frontal_face_detector(), out);
    out.close();
    if (!out) {
      std::fprintf(stderr, "cannot write '%s'\n", argv[1]);
      return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cannot write '%s': %s\n", argv[1], e.what());
    return 1;
  }
  return 0;
}
