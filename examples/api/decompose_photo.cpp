// decompose_photo PHOTO [OUT.png]: decomposes every face of PHOTO with facetool's shipped model,
// prints each face's light in the photo's frame and, with OUT.png, writes the photo relit from
// the left (docs/api.md).
#include <iostream>

#include "core/backend/registry.h"
#include "libs/face/face_detector.h"
#include "libs/inference/decomposer.h"
#include "libs/inference/model_loading.h"
#include "libs/io/image_io.h"
#include "libs/photo/photo_pipeline.h"
#include "libs/photo/relight_pipeline.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: decompose_photo PHOTO [OUT.png]\n";
    return 2;
  }
  try {
    facetool::Backend& backend = facetool::get_backend("cpu");
    facetool::PluginLoader plugins;
    plugins.set_search_dirs(facetool::library_plugin_dirs());
    plugins.discover();
    const facetool::DecompositionModel model = facetool::load_decomposition_model(plugins, backend);
    facetool::Decomposer decomposer(*model.network, *model.renderer);
    decomposer.set_landmark_normals(model.landmark_normals.get());  // the weights' head, as infer uses it
    facetool::FaceDetector detector;
    facetool::PhotoDecomposer photos(detector, decomposer, backend, model.input_size, {});

    const facetool::DecomposedPhoto photo = photos.decompose_file(argv[1]);
    for (size_t k = 0; k < photo.crops.size(); ++k) {
      std::cout << "face " << k << ": score " << photo.crops[k].face.score << ", light (photo frame, R):";
      for (int i = 0; i < 9; ++i) std::cout << " " << photo.photo_lights[k][i];
      std::cout << "\n";
    }
    if (argc > 2) {
      facetool::sh::RgbLight light{};  // ambient plus light from the viewer's left (-X)
      for (int c = 0; c < 3; ++c) {
        light[c * 9 + 0] = 3.0;
        light[c * 9 + 3] = -1.5;  // coefficient l=1, m=1 (x)
      }
      const facetool::RelitPhoto relit = facetool::relight_photo(photo, light, {}, *model.renderer, backend);
      facetool::write_png_atomically(argv[2], relit.image);
      std::cout << "relit photo: " << argv[2] << "\n";
    }
  } catch (const facetool::Error& e) {
    std::cerr << "decompose_photo: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
