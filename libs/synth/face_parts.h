// Which part of the head each triangle of the ICT Face Model belongs to, and which parts we keep.
#pragma once

#include <cstdint>
#include <string>

namespace facetool {

enum class FacePart : uint8_t {
  kFace,         // the face region (material M_Face), plus the inner lip rim
  kHeadNeck,     // back of the head, ears and neck (M_BackHead outside the sockets)
  kEyeSocket,    // the skin lining the eye sockets (M_BackHead)
  kSclera,       // eye whites: the outer eyeball shell (M_ScleraLeft/Right) minus its cornea
  kIris,         // the inner eyeball shell (M_IrisLeft/Right): iris and pupil seen through the
                 // cornea opening
  kCornea,       // the front cap of the outer shell, over the iris (dropped: it is clear)
  kMouthSocket,  // the oral cavity lining (M_BackHead, dropped)
  kGumsTongue,   // M_GumsTongue (dropped)
  kTeeth,        // M_Teeth (dropped)
  kEyeOverlay,   // transparent helper shells: M_LacrimalFluid, M_EyeBlend, M_EyeOcclusion,
                 // M_EyeLashes (dropped: as opaque geometry they would hide the eyes)
  kOther,        // any other material (kept; a user's own mesh is all kOther)
};

// True for the parts the generator renders and casts visibility rays against.
bool is_kept_part(FacePart part);
// True for the parts inside the face region, the sample's mask: kFace (the ICT face region,
// M_Face = exactly the polygons whose vertices are all < 9409, plus the inner lip rim), the eye
// sockets and eyeballs seen through the eye openings, and kOther (a user's own mesh is all face).
// False for kHeadNeck (back of the head, ears, neck) and the dropped parts.
bool is_face_region_part(FacePart part);
// "face", "head_neck", ... for messages and documentation.
const char* face_part_name(FacePart part);

// The ICT Face Model's published vertex layout (identical in the upstream FaceXModel files and in
// the vertex-only copies): the face region and the oral cavity occupy fixed vertex ranges.
struct IctVertexLayout {
  static constexpr int32_t kVertexCount = 26719;
  static constexpr int32_t kFaceRegionEnd = 9409;      // vertices [0, 9409): the face region
  static constexpr int32_t kMouthSocketBegin = 11248;  // [11248, 13294): the mouth socket
  static constexpr int32_t kMouthSocketEnd = 13294;
  static constexpr int32_t kEyeSocketEnd = 14062;      // [13294, 14062): the eye sockets
};

// The part of one polygon of the ICT neutral mesh, from its material and vertex indices.
// Rule (documented in docs/synthetic-data.md): the material decides, except for M_BackHead,
// whose polygons are the mouth socket when all their vertices lie in the mouth-socket range,
// the inner lip rim (kFace) when some do, and the eye socket or head/neck by vertex range
// otherwise. `layout_known` is false for meshes with another vertex count: then M_BackHead is
// all kHeadNeck.
FacePart classify_ict_polygon(const std::string& material, const int32_t* vertices, int count,
                              bool layout_known);

}  // namespace facetool
