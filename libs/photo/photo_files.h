// The files `facetool infer` writes per photo from a DecomposedPhoto, and its loop over photos.
#pragma once

#include <string>
#include <vector>

#include "libs/photo/photo_pipeline.h"

namespace facetool {

// Writes into `folder` (created if needed) faces.json (boxes, scores, landmarks, transforms,
// lights in the photo's frame) and the outputs in options.outputs (photo_outputs.h): one
// face_<k>/ folder per face (decomposition_files.h), albedo, shading, reconstruction, normal and
// visibility PNGs at the photo's resolution (over the photo, or transparent outside the faces
// with options.transparent), photo.exr (every channel, alpha = face coverage; the photo and
// alpha 32-bit, the network's layers 16-bit half floats) and contact_sheet.png. Files of outputs
// not asked for are neither written nor removed. facetool::Error when `photo` lacks a layer the
// outputs need (photo.layers.made).
void write_photo_files(const std::string& folder, const DecomposedPhoto& photo, const PhotoInferOptions& options);

// The bytes of one photo-level layer PNG as write_photo_files writes it over the photo (not
// transparent): `layer` is "albedo", "shading", "reconstruction", "normal" or "visibility".
std::vector<unsigned char> encode_photo_layer_png(const DecomposedPhoto& photo, const std::string& layer);


// Runs every photo `photos[k]` into <out_dir>/<folders[k]>/; a photo that cannot be read or has
// no face gets a line on stderr and the run goes on. Returns the number of such photos. Each
// photo's files are written on a worker thread while the next photo is processed, and land
// together: all of a photo's files or none of them (a WriteBatch, one flush per photo).
int infer_photos(const std::vector<std::string>& photos, const std::vector<std::string>& folders,
                 const std::string& out_dir, PhotoDecomposer& decomposer, const PhotoInferOptions& options);

}  // namespace facetool
