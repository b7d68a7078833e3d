// CropFraming: how a face is framed in the network's square crop (zoom and centre relative to
// v1's framing, and what fills the crop outside the photo), shared by synth, alignment and models.
#pragma once

#include <string>

namespace facetool {

// What the crop shows where it reaches beyond the photo (libs/image/border_fill.h).
enum class BorderFill {
  kEdgeRepeat,  // the nearest edge pixel of the photo repeated (v1)
  kRingMean,    // one constant: the mean colour of the crop's pixels inside the photo next to its
                // edge; the mask is cut there too
};

// The framing maps v1's crop units ((pixel centre + 0.5) / size, [0, 1] across the crop; the
// synthetic camera at its mean field of view, libs/face/face_template.h) to this framing's:
//   u' = 0.5 + zoom * (u - centre_x),  v' = 0.5 + zoom * (v - centre_y).
// zoom > 1 shows the face larger; (centre_x, centre_y) is the point of v1's crop that lands at
// the crop's centre. Crop size (the network's input_size) is separate from the framing.
struct CropFraming {
  double zoom = 1.0;
  double centre_x = 0.5, centre_y = 0.5;
  BorderFill border = BorderFill::kEdgeRepeat;

  double to_x(double u) const { return 0.5 + zoom * (u - centre_x); }
  double to_y(double v) const { return 0.5 + zoom * (v - centre_y); }
  bool operator==(const CropFraming& o) const {
    return zoom == o.zoom && centre_x == o.centre_x && centre_y == o.centre_y && border == o.border;
  }
  bool operator!=(const CropFraming& o) const { return !(*this == o); }
};

// v1's framing (the default everywhere): the synthetic face region's bounding box spans the crop,
// the inner face (brows to chin) 44 % of its height; edge repeat outside the photo.
CropFraming v1_framing();
// v2's: zoom 1.6 about (0.5, 0.456), the middle of the inner face, so brows (y 0.15) to chin
// (0.85) fill 71 % of the crop; ring-mean fill outside the photo.
CropFraming v2_framing();

// "edge-repeat" / "ring-mean"; parse_border_fill throws facetool::Error naming `what`.
const char* border_fill_name(BorderFill fill);
BorderFill parse_border_fill(const std::string& text, const std::string& what);

// The recorded text (model metadata "framing", synth's settings and facetool:framing):
// "zoom Z centre X Y border NAME", numbers printed to round-trip exactly.
std::string framing_text(const CropFraming& framing);
// Reads framing_text's form, or a preset name ("v1", "v2"). Throws facetool::Error naming `what`
// (e.g. "weights file 'x': metadata 'framing'") and what is expected; zoom must be in
// [0.25, 8] and the centre in [0, 1].
CropFraming parse_framing(const std::string& text, const std::string& what);

}  // namespace facetool
