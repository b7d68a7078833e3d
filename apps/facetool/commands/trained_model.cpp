// Loading trained weights and face inputs (sample EXRs or plain crops) for pseudo-label and eval.
#include "apps/facetool/commands/trained_model.h"

#include <cmath>
#include <filesystem>

#include "apps/facetool/commands/component_images.h"
#include "apps/facetool/infer/network_loading.h"
#include "libs/data/training_sample.h"
#include "libs/io/exr_io.h"
#include "libs/io/image_io.h"

namespace facetool {

LoadedNetwork load_trained_network(CommandContext& context, Backend& backend,
                                   const std::string& weights_path) {
  return load_network_weights_file(context, backend, weights_path);
}

void check_sample_size(const std::string& path, int width, int height, const LoadedNetwork& net) {
  const int size = net.network->config().input_size;
  check(width == size && height == size, "sample '", path, "' is ", width, "x", height,
        " but the network takes ", size, "x", size, "; make samples of its size and framing ",
        "(prepare-real or synth --size ", size, " --framing '", framing_text(net.framing), "')");
}

FaceInput load_face_input(const std::string& path, const LoadedNetwork& net) {
  const int size = net.network->config().input_size;
  FaceInput in;
  in.path = path;
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".exr") {
    const LayeredImage header = read_exr_header(path, "facetool:");
    if (header.find_metadata("facetool:generator_version") != nullptr) {
      in.sample = true;
      in.file = read_exr(path, "facetool:");
      check_sample_size(path, in.file.width, in.file.height, net);
      const size_t plane = in.file.plane_size();
      for (const char* name : {"R", "G", "B"}) {
        const float* p = in.file.plane(in.file.require_channel(name, path));
        in.image.insert(in.image.end(), p, p + plane);
      }
      const int mask = in.file.find_channel("mask");
      if (mask >= 0)
        in.mask.assign(in.file.plane(mask), in.file.plane(mask) + plane);
      else
        in.mask.assign(plane, 1.0f);
      for (float v : in.image)
        check(std::isfinite(v), "sample '", path, "' holds a NaN or infinite pixel");
      const std::vector<double> points = sample_landmarks(in.file, path);
      in.landmarks.assign(points.begin(), points.end());
      return in;
    }
  }
  in.image = read_planar_crop(path, size);
  in.mask.assign(static_cast<size_t>(size) * size, 1.0f);
  return in;
}

}  // namespace facetool
