// Which photo-level layers are pasted back and which files `infer` writes per photo (--outputs,
// Python's layers=): names, parsing, and what each output needs computed.
#pragma once

#include <string>
#include <vector>

namespace facetool {

// The photo-level layers of PhotoLayers (photo_pipeline.h) besides alpha, which is always made.
enum class PhotoLayer { kAlbedo, kNormal, kVisibility, kShading, kReconstruction };

// A set of photo-level layers; by default every one.
class PhotoLayerSet {
 public:
  static PhotoLayerSet all() { return PhotoLayerSet(kAllBits); }
  static PhotoLayerSet none() { return PhotoLayerSet(0); }
  PhotoLayerSet() : bits_(kAllBits) {}
  bool has(PhotoLayer layer) const { return bits_ & bit(layer); }
  void add(PhotoLayer layer) { bits_ |= bit(layer); }
  void add(const PhotoLayerSet& other) { bits_ |= other.bits_; }
  bool operator==(const PhotoLayerSet& other) const { return bits_ == other.bits_; }
  bool operator!=(const PhotoLayerSet& other) const { return bits_ != other.bits_; }

 private:
  static constexpr unsigned kAllBits = 31;
  static unsigned bit(PhotoLayer layer) { return 1u << static_cast<unsigned>(layer); }
  explicit PhotoLayerSet(unsigned bits) : bits_(bits) {}
  unsigned bits_;
};

// The name of a layer ("albedo", "normal", "visibility", "shading", "reconstruction").
const char* photo_layer_name(PhotoLayer layer);
// Every layer, in PhotoLayer's order.
const std::vector<PhotoLayer>& all_photo_layers();
// A list of layer names as a set; facetool::Error naming `what` and the valid names for an
// unknown or repeated one, or for an empty list.
PhotoLayerSet parse_photo_layers(const std::vector<std::string>& names, const std::string& what);

// The files and folders `infer` writes per photo, by --outputs name. faces.json is written
// whatever the list (it says where the faces are and holds their lights); kFaces alone asks for
// nothing else.
enum class PhotoOutput {
  kAlbedo,          // albedo.png
  kNormal,          // normal.png
  kVisibility,      // visibility.png
  kShading,         // shading.png
  kReconstruction,  // reconstruction.png
  kExr,             // photo.exr (every layer)
  kFaces,           // faces.json (always written)
  kContactSheet,    // contact_sheet.png
  kFaceFolders,     // face_<k>/ with the crop-level files (decomposition_files.h)
};

// A set of per-photo outputs; by default every one (infer without --outputs).
class PhotoOutputs {
 public:
  static PhotoOutputs all() { return PhotoOutputs(kAllBits); }
  PhotoOutputs() : bits_(kAllBits) {}
  bool has(PhotoOutput output) const { return bits_ & bit(output); }
  void remove(PhotoOutput output) { bits_ &= ~bit(output); }
  bool is_all() const { return bits_ == kAllBits; }
  // The photo-level layers these outputs read: a layer's PNG needs that layer, photo.exr every
  // one; faces.json, the contact sheet and the face folders need none (they are crop-level).
  PhotoLayerSet layers() const;
  // The names in this set, comma-separated, in PhotoOutput's order.
  std::string names() const;

  // "albedo,normal,..." (comma-separated, spaces allowed around names; "all": every output).
  // facetool::Error naming `what` and listing the valid names for an unknown name or an empty list.
  static PhotoOutputs parse(const std::string& list, const std::string& what);
  // Every valid name, comma-separated, for help texts and messages.
  static std::string valid_names();

 private:
  static constexpr unsigned kAllBits = 511;
  static unsigned bit(PhotoOutput output) { return 1u << static_cast<unsigned>(output); }
  explicit PhotoOutputs(unsigned bits) : bits_(bits) {}
  unsigned bits_;
};

}  // namespace facetool
