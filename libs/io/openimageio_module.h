// The entry point of facetool_openimageio.so, the module through which facetool reads images other than JPEG and PNG and writes GIFs.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "libs/io/image_file.h"

// Bumped whenever this table or ImageFileReader changes: a module of another version is refused.
#define FACETOOL_OPENIMAGEIO_MODULE_VERSION 1
#define FACETOOL_OPENIMAGEIO_MODULE_ENTRY_SYMBOL "facetool_openimageio_module"

namespace facetool {

struct OpenImageIoModule {
  int version = FACETOOL_OPENIMAGEIO_MODULE_VERSION;
  // open_image_file (image_file.h) for any format OpenImageIO reads; throws facetool::Error.
  std::unique_ptr<ImageFileReader> (*open)(const std::string& path, const std::string& kind) = nullptr;
  // write_gif_frames (image_file.h); throws facetool::Error.
  void (*write_gif)(const std::string& path, int width, int height,
                    const std::vector<std::vector<uint8_t>>& frames, int frames_per_second) = nullptr;
};

}  // namespace facetool

extern "C" {
using facetool_openimageio_module_fn = const facetool::OpenImageIoModule* (*)();
}
