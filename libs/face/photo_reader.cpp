// Photo reading with EXIF orientation.
#include "libs/face/photo_reader.h"

#include "core/util/stage_timer.h"

namespace facetool {

RgbImage apply_exif_orientation(const RgbImage& in, int orientation) {
  if (orientation < 2 || orientation > 8) return in;
  const bool swap = orientation >= 5;  // 5-8 transpose the axes
  RgbImage out;
  out.width = swap ? in.height : in.width;
  out.height = swap ? in.width : in.height;
  out.pixels.resize(in.pixels.size());
  const int w = in.width, h = in.height;
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      int sx = x, sy = y;  // the stored pixel shown at (x, y)
      switch (orientation) {
        case 2: sx = w - 1 - x; break;                   // mirrored horizontally
        case 3: sx = w - 1 - x; sy = h - 1 - y; break;  // rotated 180
        case 4: sy = h - 1 - y; break;                   // mirrored vertically
        case 5: sx = y; sy = x; break;                   // transposed
        case 6: sx = y; sy = h - 1 - x; break;           // rotate 90 clockwise to view
        case 7: sx = w - 1 - y; sy = h - 1 - x; break;   // transverse
        case 8: sx = w - 1 - y; sy = x; break;           // rotate 90 counter-clockwise to view
      }
      const float* s = in.at(sx, sy);
      float* d = out.at(x, y);
      d[0] = s[0];
      d[1] = s[1];
      d[2] = s[2];
    }
  return out;
}

RgbImage read_photo(const std::string& path) {
  StageTimer timer("decode");
  int orientation = 1;
  RgbImage stored = read_rgb_image_as_encoded(path, orientation, "photo");
  if (orientation == 1) return stored;
  return apply_exif_orientation(stored, orientation);
}

}  // namespace facetool
