// Whole photos: detection, alignment, the network on each face's crop, and everything pasted back
// at the photo's resolution (docs/photos.md). PhotoDecomposer works on photos in memory; the
// files `infer` writes from its results are photo_files.h's.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/backend/backend.h"
#include "libs/face/face_crops.h"
#include "libs/face/face_detector.h"
#include "libs/face/guided_paste.h"
#include "libs/face/paste_back.h"
#include "libs/image/crop_framing.h"
#include "libs/inference/batched_decomposition.h"
#include "libs/inference/decomposer.h"
#include "libs/photo/photo_outputs.h"
#include "core/sh/sh_types.h"
#include "core/util/error.h"

namespace facetool {

class FitBasis;
class PhotoFitter;

// Where each face's results paste back (--face-region): the landmarks' convex hull, or the hull
// extended over the forehead (libs/face/face_mask.h). kAuto: the forehead hull for models at any
// framing but v1's (their stage-2 labels, the fit's mask, cover the forehead, as synthetic
// samples' masks do), the hull at v1's (whose real samples' masks were the hull).
enum class FaceRegion { kAuto, kHull, kForehead };

// "auto", "hull", "forehead"; parse_face_region throws facetool::Error naming `what`.
FaceRegion parse_face_region(const std::string& text, const std::string& what);

struct PhotoInferOptions {
  DetectionOptions detection;
  std::string landmark_model = kDefaultLandmarkModel;
  std::string cnn_model = kDefaultCnnFaceModel;  // --cnn-model
  FaceRegion region = FaceRegion::kAuto;  // --face-region
  double feather = 3.0;          // --feather, crop pixels
  // --upsample: albedo and normals pasted back guided by the photo (the default) or bilinear.
  Upsample upsample = Upsample::kGuided;
  // The framing the model was trained at (its weights' "framing" metadata; v1 by default).
  CropFraming framing;
  bool transparent = false;      // --transparent: PNGs transparent outside the faces
  // The photo-level layers pasted back (Python's layers=; infer: those its outputs need). The
  // network, light solve and crop-level render run whatever the set: the light and albedo of
  // every face follow from them.
  PhotoLayerSet layers;
  // The files write_photo_files writes per photo (--outputs; --no-contact-sheet takes one out).
  // Its layers() must be in `layers`.
  PhotoOutputs outputs;
  int batch = 8;
  const PhotoFitter* with_fit = nullptr;  // --with-fit: the landmark fit too, in <photo folder>/fit/
  // The face model for a network that takes the fit's normals as input (NetworkConfig::
  // input_prior "fit_normal"; --face-model): each crop's landmarks fitted (fit_prior_normals).
  const FitBasis* prior_basis = nullptr;

  // Whether the face region extends over the forehead: `region`, with kAuto resolved by `framing`.
  bool extends_forehead() const;
};

// Float planes of the photo's size that pasting back and writing `options`' layers and outputs
// hold at once (47 with every output): the memory check before a photo's paste-back.
uint64_t photo_planes(const PhotoInferOptions& options);

// What the network reads for `crops`: each crop's planar RGB, followed by its input prior when
// `network` takes one (the fit of the crop's landmarks on `prior_basis`, which must then be
// given; facetool::Error otherwise).
std::vector<float> network_inputs(const std::vector<FaceCrop>& crops, const NetworkConfig& network,
                                  const FitBasis* prior_basis);

// PHOTO|DIR arguments as photo files: a folder gives its image files (by extension, sorted, not
// recursive). Throws facetool::Error for a path that is neither.
std::vector<std::string> expand_photo_inputs(const std::vector<std::string>& inputs);

// Detection and alignment: each face of `photo` (linear RGB) cropped to crop_size at
// options.framing, best detection score first (empty: no face). PhotoDecomposer's first step;
// prepare-real's whole job.
std::vector<FaceCrop> find_face_crops(FaceDetector& detector, const RgbImage& photo, int crop_size,
                                      const PhotoInferOptions& options);

// Photo-resolution planar layers, premultiplied by the faces' coverage `alpha` (0 where no face
// is). Normals and visibility are turned into the photo's frame (+X right, +Y up, +Z towards
// the viewer; libs/face/frame_rotation.h).
struct PhotoLayers {
  int width = 0, height = 0;
  std::vector<float> alpha;           // [w*h] face coverage in [0, 1]
  std::vector<float> albedo;          // [3][w*h]
  std::vector<float> normal;          // [3][w*h]
  std::vector<float> visibility;      // [9][w*h] SH coefficients
  std::vector<float> shading;         // [3][w*h]
  std::vector<float> reconstruction;  // [3][w*h]
  // The layers made (PhotoInferOptions::layers); the others are left empty.
  PhotoLayerSet made;
};

// A photo taken apart once: its faces' crops (best detection score first), the network's
// crop-level results (crop frame), where each face pastes back, each face's light turned into
// the photo's frame, and the layers pasted back at the photo's resolution.
// Thrown by PhotoDecomposer::decompose when the photo holds no face; reason() says why where
// that is known (face_detector.h's no_face_reason).
class NoFaceError : public Error {
 public:
  NoFaceError(const std::string& message, std::string reason) : Error(message), reason_(std::move(reason)) {}
  const std::string& reason() const { return reason_; }

 private:
  std::string reason_;
};

// The face detector the options ask for (--landmark-model, --cnn-model, --detector), its models
// loaded now so that a missing or damaged one is reported before any photo is read.
std::unique_ptr<FaceDetector> make_face_detector(const PhotoInferOptions& options);

struct DecomposedPhoto {
  std::string path;  // the source named in messages and files ("" for a photo given in memory)
  RgbImage photo;    // linear RGB
  int crop_size = 0;
  std::vector<FaceCrop> crops;
  Decomposition decomposition;             // one image per crop
  std::vector<PasteRegion> regions;        // per face
  std::vector<sh::RgbLight> photo_lights;  // per face, photo frame (docs/photos.md)
  PhotoLayers layers;
};

// A photo whose faces are found and aligned, waiting for the network (PhotoDecomposer::find).
struct FoundPhoto {
  std::string path;  // as DecomposedPhoto's
  RgbImage photo;    // linear RGB
  std::vector<FaceCrop> crops;  // best detection score first; never empty
};

// The photo pipeline on photos in memory: detect, align, decompose every face in batches, paste
// back. The detector, decomposer and backend must outlive it.
class PhotoDecomposer {
 public:
  // `crop_size`: the network's input size.
  PhotoDecomposer(FaceDetector& detector, Decomposer& decomposer, Backend& backend, int crop_size,
                  const PhotoInferOptions& options);

  // Detection and alignment only: each face's crop, best detection score first (empty: none).
  std::vector<FaceCrop> find_faces(const RgbImage& photo);

  // `photo` in linear RGB. Throws facetool::Error naming `source` (or "the photo") when it holds
  // no face.
  DecomposedPhoto decompose(RgbImage photo, const std::string& source = "");
  // decompose() in two steps, so that the faces of several photos share the network's batches
  // (infer on many photos): find() detects and aligns, and throws as decompose() does;
  // decompose_found() runs the network on every photo's faces together, options().batch at a
  // time, and pastes each photo's back (results in the order given).
  FoundPhoto find(RgbImage photo, const std::string& source = "");
  std::vector<DecomposedPhoto> decompose_found(std::vector<FoundPhoto> photos);
  // decompose_found() up to the paste-back: each photo's faces from the network (one
  // Decomposition per photo, in the order given), for assemble() to paste back later, on
  // another thread (infer's writer).
  std::vector<Decomposition> decompose_faces(const std::vector<FoundPhoto>& photos);
  // The paste-back of one photo found by find() with its decompose_faces() result, with this
  // decomposer's feathering and upsampling (assemble_decomposed_photo).
  DecomposedPhoto assemble(FoundPhoto photo, const Decomposition& faces) const;

  // read_photo(path) (8-bit files decoded from sRGB), then decompose(); throws facetool::Error
  // naming the file when it cannot be read or holds no face.
  DecomposedPhoto decompose_file(const std::string& path);

  const PhotoInferOptions& options() const { return options_; }
  int crop_size() const { return crop_size_; }

 private:
  FaceDetector& detector_;
  Decomposer& decomposer_;
  Backend& backend_;
  int crop_size_;
  PhotoInferOptions options_;
};

// The part of decompose() after the network: paste regions, the photo-frame layers, the
// estimated shading at the photo's resolution and each face's light turned into the photo's
// frame. `decomposition` holds one face per crop (the tests give synthetic ones). With
// Upsample::kGuided, albedo and normals go through paste_channels_guided (guided_paste.h);
// everything else, and everything with kBilinear, through paste_channels. Only the layers in
// `layers` are pasted back (alpha always); the others stay empty.
DecomposedPhoto assemble_decomposed_photo(const std::string& path, RgbImage photo, std::vector<FaceCrop> crops,
                                          const Decomposition& decomposition, double feather,
                                          Upsample upsample = Upsample::kBilinear,
                                          PhotoLayerSet layers = PhotoLayerSet::all());

// Face k's crop-level planes of `d`: `channels` planes of S*S from the array `all` ([N][C][S][S]).
std::vector<float> face_planes(const std::vector<float>& all, int k, int channels, int crop_size);

}  // namespace facetool
