// The photo pipeline in memory: detect, align, decompose every face, paste the layers back.
#include "libs/photo/photo_pipeline.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <iostream>

#include "libs/face/frame_rotation.h"
#include "libs/fit/fit_prior.h"
#include "libs/face/photo_reader.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "core/util/memory_budget.h"
#include "core/util/stage_timer.h"
#include "core/util/terminal_text.h"

namespace fs = std::filesystem;

namespace facetool {
namespace {

bool is_photo_file(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const char* e : {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp", ".webp", ".exr", ".hdr", ".pgm", ".ppm"})
    if (ext == e) return true;
  return false;
}

}  // namespace

std::vector<float> face_planes(const std::vector<float>& all, int k, int channels, int crop_size) {
  const size_t size = static_cast<size_t>(channels) * crop_size * crop_size;
  check((static_cast<size_t>(k) + 1) * size <= all.size(), "face ", k, " is not in the decomposition");
  return std::vector<float>(all.begin() + k * size, all.begin() + (k + 1) * size);
}

PhotoDecomposer::PhotoDecomposer(FaceDetector& detector, Decomposer& decomposer, Backend& backend,
                                 int crop_size, const PhotoInferOptions& options)
    : detector_(detector), decomposer_(decomposer), backend_(backend), crop_size_(crop_size), options_(options) {
  check(crop_size >= 8, "photo decomposer: the crop size must be at least 8 pixels (it is ", crop_size, ")");
  check(options.batch >= 1, "photo decomposer: the batch size must be at least 1 (it is ", options.batch, ")");
  check(options.feather >= 0, "photo decomposer: the feather must be 0 or more (it is ", options.feather, ")");
  check(decomposer.network().config().input_prior.empty() || options.prior_basis != nullptr,
        "photo decomposer: the network takes the input prior '", decomposer.network().config().input_prior,
        "' (the fit's normals): give the face model (--face-model DIR)");
}

std::vector<float> network_inputs(const std::vector<FaceCrop>& crops, const NetworkConfig& network,
                                  const FitBasis* prior_basis) {
  const bool prior = !network.input_prior.empty();
  check(!prior || prior_basis != nullptr, "the network takes the input prior '", network.input_prior,
        "' (the fit's normals): give the face model (--face-model DIR)");
  const FitSettings settings = prior ? prior_fit_settings(network.input_prior) : FitSettings{};
  std::vector<float> inputs;
  for (const FaceCrop& c : crops) {
    inputs.insert(inputs.end(), c.rgb.begin(), c.rgb.end());
    if (!prior) continue;
    LandmarkTarget target;
    target.landmarks = c.alignment.crop_landmarks;
    target.width = target.height = c.alignment.crop_size;
    StageTimer timer("fit prior");  // the landmark fit and its normals rendered at the crop
    const std::vector<float> normals = fit_prior_normals(*prior_basis, target, settings);
    inputs.insert(inputs.end(), normals.begin(), normals.end());
  }
  return inputs;
}

FaceRegion parse_face_region(const std::string& text, const std::string& what) {
  if (text == "auto") return FaceRegion::kAuto;
  if (text == "hull") return FaceRegion::kHull;
  if (text == "forehead") return FaceRegion::kForehead;
  fail(what, " must be auto, hull or forehead, not '", text, "'");
}

bool PhotoInferOptions::extends_forehead() const {
  if (region == FaceRegion::kAuto) return framing != v1_framing();
  return region == FaceRegion::kForehead;
}

std::unique_ptr<FaceDetector> make_face_detector(const PhotoInferOptions& options) {
  auto detector = std::make_unique<FaceDetector>(options.landmark_model, options.cnn_model);
  detector->prepare(options.detection.detector);
  return detector;
}

std::vector<FaceCrop> find_face_crops(FaceDetector& detector, const RgbImage& photo, int crop_size,
                                      const PhotoInferOptions& options) {
  std::vector<FaceCrop> crops;
  for (const DetectedFace& f : detector.detect(photo, options.detection))
    crops.push_back(crop_face(photo, f, crop_size, options.extends_forehead(), options.framing));
  return crops;
}

// Float planes of the photo's size that the paste-back and the files of `options` hold at once:
// the coverage, the layers asked for (albedo, normal, shading and reconstruction 3 each, the
// visibility 9) and, with photo.exr, its 25 channels.
uint64_t photo_planes(const PhotoInferOptions& options) {
  uint64_t planes = 1;
  for (const PhotoLayer layer : all_photo_layers())
    if (options.layers.has(layer)) planes += layer == PhotoLayer::kVisibility ? 9 : 3;
  if (options.outputs.has(PhotoOutput::kExr)) planes += 25;
  return planes;
}

std::vector<FaceCrop> PhotoDecomposer::find_faces(const RgbImage& photo) {
  return find_face_crops(detector_, photo, crop_size_, options_);
}

FoundPhoto PhotoDecomposer::find(RgbImage photo, const std::string& source) {
  const std::string named = source.empty() ? std::string("the photo") : "photo '" + source + "'";
  check(photo.width > 0 && photo.height > 0 &&
            photo.pixels.size() == static_cast<size_t>(photo.width) * photo.height * 3,
        named, " is not a ", photo.width, "x", photo.height, " RGB image (", photo.pixels.size(), " values)");
  std::vector<FaceCrop> crops = find_faces(photo);
  if (crops.empty()) {
    const std::string reason = no_face_reason(photo, options_.detection);
    throw NoFaceError(named + ": " + reason, reason);
  }
  check_memory_budget(static_cast<uint64_t>(photo.width) * photo.height * photo_planes(options_) * sizeof(float),
                      "pasting the faces back into " + named + " of " + std::to_string(photo.width) + "x" +
                          std::to_string(photo.height) + " pixels");
  return {source, std::move(photo), std::move(crops)};
}

std::vector<DecomposedPhoto> PhotoDecomposer::decompose_found(std::vector<FoundPhoto> photos) {
  const std::vector<Decomposition> faces = decompose_faces(photos);
  std::vector<DecomposedPhoto> out;
  for (size_t i = 0; i < photos.size(); ++i) out.push_back(assemble(std::move(photos[i]), faces[i]));
  return out;
}

DecomposedPhoto PhotoDecomposer::assemble(FoundPhoto photo, const Decomposition& faces) const {
  return assemble_decomposed_photo(photo.path, std::move(photo.photo), std::move(photo.crops), faces,
                                   options_.feather, options_.upsample, options_.layers);
}

std::vector<Decomposition> PhotoDecomposer::decompose_faces(const std::vector<FoundPhoto>& photos) {
  std::vector<FaceCrop> all;
  for (const FoundPhoto& p : photos) all.insert(all.end(), p.crops.begin(), p.crops.end());
  const std::vector<float> inputs = network_inputs(all, decomposer_.network().config(), options_.prior_basis);
  std::vector<float> landmarks;  // each crop's, for the landmark normal head
  for (const FaceCrop& c : all)
    for (const Point2& p : c.alignment.crop_landmarks) {
      landmarks.push_back(static_cast<float>(p.x));
      landmarks.push_back(static_cast<float>(p.y));
    }
  const Decomposition d = decompose_all(decomposer_, backend_, inputs, static_cast<int>(all.size()),
                                        crop_size_, options_.batch, &landmarks);
  std::vector<Decomposition> out;
  int first = 0;
  for (const FoundPhoto& p : photos) {
    const int n = static_cast<int>(p.crops.size());
    out.push_back(decomposition_images(d, first, n));
    first += n;
  }
  return out;
}

DecomposedPhoto PhotoDecomposer::decompose(RgbImage photo, const std::string& source) {
  std::vector<FoundPhoto> one;
  one.push_back(find(std::move(photo), source));
  return std::move(decompose_found(std::move(one)).front());
}

DecomposedPhoto PhotoDecomposer::decompose_file(const std::string& path) {
  RgbImage photo;
  try {
    photo = read_photo(path);
  } catch (const Error& e) {
    fail("photo '", path, "': ", e.what());
  }
  return decompose(std::move(photo), path);
}

DecomposedPhoto assemble_decomposed_photo(const std::string& path, RgbImage photo, std::vector<FaceCrop> crops,
                                          const Decomposition& decomposition, double feather,
                                          Upsample upsample, PhotoLayerSet made) {
  DecomposedPhoto out;
  out.path = path;
  out.photo = std::move(photo);
  out.crops = std::move(crops);
  out.decomposition = decomposition;
  const int n = decomposition.count, crop_size = decomposition.size;
  check(n == static_cast<int>(out.crops.size()), "photo pipeline: ", n, " decomposed faces for ",
        out.crops.size(), " crops");
  out.crop_size = crop_size;
  const int w = out.photo.width, h = out.photo.height;
  const size_t plane = static_cast<size_t>(w) * h, crop_plane = static_cast<size_t>(crop_size) * crop_size;
  PhotoLayers& layers = out.layers;
  layers.width = w;
  layers.height = h;
  layers.made = made;
  const bool albedo = made.has(PhotoLayer::kAlbedo), normals = made.has(PhotoLayer::kNormal);
  const bool visibilities = made.has(PhotoLayer::kVisibility), shadings = made.has(PhotoLayer::kShading);
  const bool reconstructions = made.has(PhotoLayer::kReconstruction);
  layers.alpha.assign(plane, 0.0f);
  if (albedo) layers.albedo.assign(plane * 3, 0.0f);
  if (normals) layers.normal.assign(plane * 3, 0.0f);
  if (visibilities) layers.visibility.assign(plane * 9, 0.0f);
  if (shadings) layers.shading.assign(plane * 3, 0.0f);
  if (reconstructions) layers.reconstruction.assign(plane * 3, 0.0f);
  const std::vector<float> ones(crop_plane, 1.0f);
  const bool guided = upsample == Upsample::kGuided;

  const Decomposition& d = out.decomposition;
  for (int k = 0; k < n; ++k) {
    const FaceCrop& c = out.crops[k];
    const Similarity2& t = c.alignment.photo_to_crop;
    out.regions.push_back(paste_region(w, h, t, crop_size, c.mask_polygon, feather));
    const PasteRegion& region = out.regions.back();
    paste_channels(region, ones.data(), 1, layers.alpha.data(), w, h);
    std::vector<float> normal;
    if (normals) {
      normal = face_planes(d.normal, k, 3, crop_size);
      rotate_normals_to_photo(normal.data(), crop_plane, t);
    }
    if (guided && (albedo || normals)) {
      const FaceGuide guide = face_guide(out.photo, region);
      if (albedo)
        paste_channels_guided(region, face_planes(d.albedo, k, 3, crop_size).data(), 3, guide,
                              layers.albedo.data(), w, h, false, 0.0f, 1.0f);
      if (normals)
        paste_channels_guided(region, normal.data(), 3, guide, layers.normal.data(), w, h, true, 0.0f, 0.0f);
    } else {
      if (albedo)
        paste_channels(region, face_planes(d.albedo, k, 3, crop_size).data(), 3, layers.albedo.data(), w, h);
      if (normals) paste_channels(region, normal.data(), 3, layers.normal.data(), w, h);
    }
    if (visibilities) {
      std::vector<float> visibility = face_planes(d.visibility, k, 9, crop_size);
      rotate_visibility_to_photo(visibility.data(), crop_plane, t);
      paste_channels(region, visibility.data(), 9, layers.visibility.data(), w, h);
    }
    if (shadings)
      paste_channels(region, face_planes(d.shading, k, 3, crop_size).data(), 3, layers.shading.data(), w, h);
    if (reconstructions)
      paste_channels(region, face_planes(d.reconstruction, k, 3, crop_size).data(), 3, layers.reconstruction.data(),
                     w, h);
    sh::RgbLight light;
    for (int i = 0; i < sh::kLightCoeffCount; ++i)
      light[i] = d.light[static_cast<size_t>(k) * sh::kLightCoeffCount + i];
    out.photo_lights.push_back(rotate_light_to_photo(light, t));
  }
  return out;
}

std::vector<std::string> expand_photo_inputs(const std::vector<std::string>& inputs) {
  std::vector<std::string> photos;
  for (const std::string& input : inputs) {
    std::error_code ec;
    if (fs::is_directory(input, ec)) {
      // Links that lead nowhere (dangling, loops) and pipes are named and skipped, not fatal.
      std::vector<std::string> problems;
      const std::vector<std::string> found = list_folder_files(
          input, "photo folder", [](const std::string& name) { return is_photo_file(name); },
          problems);
      for (const std::string& problem : problems)
        std::cerr << "skipping " << printable_text(problem) << "\n";
      check(!found.empty(), "folder '", input, "' holds no photos (png, jpg, jpeg, tif, tiff, bmp, webp, exr, hdr, pgm, ppm)");
      photos.insert(photos.end(), found.begin(), found.end());
    } else {
      check_regular_input_file(input, kMaxImageFileBytes, "input photo");
      photos.push_back(input);
    }
  }
  return photos;
}

}  // namespace facetool
