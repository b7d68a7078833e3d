// open_image_file: JPEG and PNG told by their first bytes and decoded here, any other format through the OpenImageIO module, loaded on first use.
#include "libs/io/image_file.h"

#include <cstring>
#include <fstream>
#include <string>
#include <mutex>

#include "core/util/error.h"
#include "core/util/memory_budget.h"
#include "core/util/shared_library.h"
#include "libs/io/jpeg_decoding.h"
#include "libs/io/openimageio_module.h"
#include "libs/io/png_decoding.h"

namespace facetool {
namespace {

constexpr const char* kModuleFile = "facetool_openimageio.so";
// The address space loading the module takes: OpenImageIO and the libraries it links map about
// 0.4 GB of files, and a logging library among them starts threads while it loads (measured
// 0.38 GB of files and 0.2 GB of stacks and heaps). Under a tighter address-space limit the
// loader fails to map a library, or that library's start aborts the process, so the budget is
// checked first. 0.52 GB: with 0.45 a run under 700 MB still crashed inside the library; with 0.6
// eval was refused under 900 MB, where it works (docs/input-limits.md).
constexpr uint64_t kModuleAddressSpace = 520ull << 20;
constexpr const char* kModuleTask = "loading the module that reads EXR and other formats through OpenImageIO";

// Whether the loader's message says that it ran out of memory mapping a library.
bool loader_out_of_memory(const std::string& message) {
  return message.find("failed to map segment") != std::string::npos ||
         message.find("Cannot allocate memory") != std::string::npos;
}

// Loads the module: its table, or null with `failure` saying why. Throws OutOfMemory where the
// loader ran out of memory mapping a library.
const OpenImageIoModule* load_module(std::string& failure) {
  const std::string path = find_module_file(kModuleFile, "FACETOOL_BACKEND_PATH", failure);
  if (path.empty()) {
    failure += " (reinstall facetool)";
    return nullptr;
  }
  try {
    SharedLibrary library = SharedLibrary::open(path);
    auto entry = reinterpret_cast<facetool_openimageio_module_fn>(
        library.symbol(FACETOOL_OPENIMAGEIO_MODULE_ENTRY_SYMBOL));
    if (entry == nullptr) {
      failure = path + " does not export " FACETOOL_OPENIMAGEIO_MODULE_ENTRY_SYMBOL + std::string("; rebuild facetool");
    } else if (entry()->version != FACETOOL_OPENIMAGEIO_MODULE_VERSION) {
      failure = path + " is of another facetool version (module version " + std::to_string(entry()->version) +
                ", facetool's " + std::to_string(FACETOOL_OPENIMAGEIO_MODULE_VERSION) + "); rebuild or reinstall facetool";
    } else {
      return entry();
    }
  } catch (const Error& e) {
    if (loader_out_of_memory(e.what())) throw out_of_memory(kModuleTask, kModuleAddressSpace);
    failure = std::string(e.what()) + " (is OpenImageIO installed? apt-get install libopenimageio2.4)";
  }
  return nullptr;
}

// The module's table, loaded once per process (thread-safe); null if it cannot be loaded, with
// `why` saying why (the same for every later call). Throws OutOfMemory, before loading it, where
// the memory left cannot hold it; a later call tries again.
const OpenImageIoModule* openimageio_module(std::string& why) {
  static std::mutex mutex;
  static bool loaded = false;
  static const OpenImageIoModule* module = nullptr;
  static std::string failure;
  std::lock_guard<std::mutex> lock(mutex);
  if (!loaded) {
    check_memory_budget(kModuleAddressSpace, kModuleTask);
    module = load_module(failure);
    loaded = true;
  }
  why = failure;
  return module;
}

enum class Format { kJpeg, kPng, kOther };

Format sniff(const std::string& path) {
  unsigned char magic[8] = {};
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(magic), sizeof magic);
  const std::streamsize got = in.gcount();
  if (got >= 3 && magic[0] == 0xff && magic[1] == 0xd8 && magic[2] == 0xff) return Format::kJpeg;
  if (got == 8 && std::memcmp(magic, "\x89PNG\r\n\x1a\n", 8) == 0) return Format::kPng;
  return Format::kOther;
}

}  // namespace

std::unique_ptr<ImageFileReader> open_image_file(const std::string& path, const std::string& kind) {
  switch (sniff(path)) {
    case Format::kJpeg: return open_jpeg_file(path, kind);
    case Format::kPng: return open_png_file(path, kind);
    case Format::kOther: break;
  }
  std::string why;
  const OpenImageIoModule* module = openimageio_module(why);
  check(module != nullptr, "cannot read ", kind, " '", path, "': it is neither JPEG nor PNG, and the module ",
        "that reads other formats through OpenImageIO cannot be loaded: ", why);
  return module->open(path, kind);
}

void write_gif_frames(const std::string& path, int width, int height,
                      const std::vector<std::vector<uint8_t>>& frames, int frames_per_second) {
  std::string why;
  const OpenImageIoModule* module = openimageio_module(why);
  check(module != nullptr, "cannot write animated GIF '", path, "': the module that writes GIFs through ",
        "OpenImageIO cannot be loaded: ", why);
  module->write_gif(path, width, height, frames, frames_per_second);
}

}  // namespace facetool
