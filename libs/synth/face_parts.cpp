// The ICT Face Model part rule: materials first, vertex ranges inside M_BackHead.
#include "libs/synth/face_parts.h"

namespace facetool {

bool is_kept_part(FacePart part) {
  switch (part) {
    case FacePart::kMouthSocket:
    case FacePart::kGumsTongue:
    case FacePart::kTeeth:
    case FacePart::kEyeOverlay:
    case FacePart::kCornea:
      return false;
    default:
      return true;
  }
}

bool is_face_region_part(FacePart part) {
  switch (part) {
    case FacePart::kFace:
    case FacePart::kEyeSocket:
    case FacePart::kSclera:
    case FacePart::kIris:
    case FacePart::kOther:
      return true;
    default:
      return false;
  }
}

const char* face_part_name(FacePart part) {
  switch (part) {
    case FacePart::kFace: return "face";
    case FacePart::kHeadNeck: return "head_neck";
    case FacePart::kEyeSocket: return "eye_socket";
    case FacePart::kSclera: return "sclera";
    case FacePart::kIris: return "iris";
    case FacePart::kCornea: return "cornea";
    case FacePart::kMouthSocket: return "mouth_socket";
    case FacePart::kGumsTongue: return "gums_tongue";
    case FacePart::kTeeth: return "teeth";
    case FacePart::kEyeOverlay: return "eye_overlay";
    case FacePart::kOther: return "other";
  }
  return "unknown";
}

FacePart classify_ict_polygon(const std::string& material, const int32_t* vertices, int count,
                              bool layout_known) {
  if (material == "M_Face") return FacePart::kFace;
  if (material == "M_GumsTongue") return FacePart::kGumsTongue;
  if (material == "M_Teeth") return FacePart::kTeeth;
  if (material == "M_ScleraLeft" || material == "M_ScleraRight") return FacePart::kSclera;
  if (material == "M_IrisLeft" || material == "M_IrisRight") return FacePart::kIris;
  if (material == "M_LacrimalFluid" || material == "M_EyeBlend" ||
      material == "M_EyeOcclusion" || material == "M_EyeLashes")
    return FacePart::kEyeOverlay;
  if (material != "M_BackHead") return FacePart::kOther;
  if (!layout_known) return FacePart::kHeadNeck;
  using L = IctVertexLayout;
  int in_mouth = 0, in_eye_socket = 0;
  for (int k = 0; k < count; ++k) {
    const int32_t v = vertices[k];
    if (v >= L::kMouthSocketBegin && v < L::kMouthSocketEnd) ++in_mouth;
    if (v >= L::kMouthSocketEnd && v < L::kEyeSocketEnd) ++in_eye_socket;
  }
  if (in_mouth == count) return FacePart::kMouthSocket;
  if (in_mouth > 0) return FacePart::kFace;  // the strip joining the lips to the mouth socket
  if (in_eye_socket > 0) return FacePart::kEyeSocket;
  return FacePart::kHeadNeck;
}

}  // namespace facetool
