// Animated GIF files written with OpenImageIO (built with giflib on Debian), atomically.
#include "libs/relight/animated_gif.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdint>
#include <memory>

#include "core/util/atomic_file.h"
#include "core/util/error.h"

namespace facetool {

void write_animated_gif(const std::string& path, const std::vector<RgbImage>& frames,
                        int frames_per_second) {
  check(!frames.empty(), "animated GIF '", path, "': no frames to write");
  check(frames_per_second >= 1, "animated GIF '", path, "': frames per second must be at least 1");
  const int w = frames[0].width, h = frames[0].height;
  for (const RgbImage& f : frames)
    check(f.width == w && f.height == h, "animated GIF '", path, "': frames differ in size");
  write_atomically(path, [&](const std::string& temporary) {
    // The temporary name has no .gif extension, so the format is named explicitly.
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create("gif");
    check(out != nullptr, "cannot write animated GIF '", path, "': this OpenImageIO has no GIF "
          "writer (build it with giflib); the frames are written as PNGs beside it");
    check(out->supports("multiimage") && out->supports("appendsubimage"),
          "cannot write animated GIF '", path, "': OpenImageIO's GIF writer cannot append frames");
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
    const int rate[2] = {frames_per_second, 1};
    spec.attribute("FramesPerSecond", OIIO::TypeRational, rate);
    spec.attribute("gif:LoopCount", 0);
    std::vector<OIIO::ImageSpec> specs(frames.size(), spec);
    check(out->open(temporary, static_cast<int>(specs.size()), specs.data()),
          "cannot write animated GIF '", path, "': ", out->geterror());
    std::vector<uint8_t> bytes(static_cast<size_t>(w) * h * 3);
    for (size_t k = 0; k < frames.size(); ++k) {
      if (k > 0)
        check(out->open(temporary, spec, OIIO::ImageOutput::AppendSubimage),
              "cannot append frame ", k, " to animated GIF '", path, "': ", out->geterror());
      for (size_t i = 0; i < bytes.size(); ++i) {
        const float v = linear_to_srgb(std::clamp(frames[k].pixels[i], 0.0f, 1.0f));
        bytes[i] = static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
      }
      check(out->write_image(OIIO::TypeDesc::UINT8, bytes.data()), "cannot write frame ", k,
            " of animated GIF '", path, "': ", out->geterror());
    }
    check(out->close(), "cannot finish animated GIF '", path, "': ", out->geterror());
  });
}

}  // namespace facetool
