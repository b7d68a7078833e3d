// decompose_photo PHOTO [OUT_DIR]: decomposes every face of PHOTO with facetool's shipped model,
// prints each face's light in the photo's frame and, with OUT_DIR, writes there the files
// `facetool infer` writes for the photo and the photo relit from the viewer's left (docs/api.md).
#include <iostream>
#include <string>

#include "libs/io/image_io.h"
#include "libs/light/direction_light.h"
#include "libs/photo/photo_files.h"
#include "libs/photo/session.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: decompose_photo PHOTO [OUT_DIR]\n";
    return 2;
  }
  try {
    facetool::Session session;  // the shipped model, the CLI's defaults
    const facetool::DecomposedPhoto photo = session.decompose_file(argv[1]);
    for (size_t k = 0; k < photo.crops.size(); ++k) {
      std::cout << "face " << k << ": score " << photo.crops[k].face.score << ", light (photo frame, R):";
      for (int i = 0; i < 9; ++i) std::cout << " " << photo.photo_lights[k][i];
      std::cout << "\n";
    }
    if (argc > 2) {
      const std::string out = argv[2];
      facetool::write_photo_files(out, photo, session.framed());  // what `facetool infer` writes
      // A light 60 degrees to the viewer's left, 20 up: ambient 0.3 plus a distant light of 1.
      const facetool::sh::RgbLight light = facetool::light::light_from_direction(-60, 20, 0.3, 1.0);
      const facetool::RelitPhoto relit = session.relight(photo, light);
      facetool::write_png_atomically(out + "/relit.png", relit.image);
      std::cout << "the decomposition and the relit photo: " << out << "\n";
    }
  } catch (const facetool::Error& e) {
    std::cerr << "decompose_photo: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
