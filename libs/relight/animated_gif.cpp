// Animated GIF files written through OpenImageIO (libs/io/image_file.h; giflib on Debian), atomically.
#include "libs/relight/animated_gif.h"

#include <algorithm>
#include <cstdint>
#include <memory>

#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "libs/io/image_file.h"

namespace facetool {

void write_animated_gif(const std::string& path, const std::vector<RgbImage>& frames,
                        int frames_per_second) {
  check(!frames.empty(), "animated GIF '", path, "': no frames to write");
  check(frames_per_second >= 1, "animated GIF '", path, "': frames per second must be at least 1");
  const int w = frames[0].width, h = frames[0].height;
  for (const RgbImage& f : frames)
    check(f.width == w && f.height == h, "animated GIF '", path, "': frames differ in size");
  std::vector<std::vector<uint8_t>> bytes(frames.size(), std::vector<uint8_t>(static_cast<size_t>(w) * h * 3));
  for (size_t k = 0; k < frames.size(); ++k)
    for (size_t i = 0; i < bytes[k].size(); ++i) bytes[k][i] = linear_to_srgb8(frames[k].pixels[i]);
  write_atomically(path, [&](const std::string& temporary) {
    write_gif_frames(temporary, w, h, bytes, frames_per_second);
  });
}

}  // namespace facetool
