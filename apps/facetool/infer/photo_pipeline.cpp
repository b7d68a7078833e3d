// The photo path of `facetool infer`: per photo, detect, align, decompose, paste back, write.
#include "apps/facetool/infer/photo_pipeline.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "apps/facetool/infer/infer_outputs.h"
#include "core/face/detection_summary.h"
#include "core/face/face_crops.h"
#include "core/face/frame_rotation.h"
#include "core/face/landmark_drawing.h"
#include "core/face/paste_back.h"
#include "core/face/photo_reader.h"
#include "core/face/rgba_png.h"
#include "core/util/atomic_file.h"
#include "core/io/exr_io.h"
#include "core/util/error.h"
#include "core/util/progress_bar.h"

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace facetool {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool is_photo_file(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const char* e : {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp", ".webp", ".exr", ".hdr", ".pgm", ".ppm"})
    if (ext == e) return true;
  return false;
}

}  // namespace

// Runs the decomposer over `count` crops in batches and concatenates the results.
Decomposition decompose_all(Decomposer& decomposer, Backend& backend, const std::vector<float>& crops,
                            int count, int size, int batch) {
  Decomposition all;
  const size_t plane = static_cast<size_t>(size) * size;
  for (int first = 0; first < count; first += batch) {
    const int n = std::min(batch, count - first);
    const std::vector<float> part(crops.begin() + first * 3 * plane, crops.begin() + (first + n) * 3 * plane);
    Decomposition d = decomposer.run(backend, part, n);
    all.size = d.size;
    all.count += n;
    auto append = [](std::vector<float>& to, const std::vector<float>& from) {
      to.insert(to.end(), from.begin(), from.end());
    };
    append(all.albedo, d.albedo);
    append(all.normal, d.normal);
    append(all.visibility, d.visibility);
    append(all.light, d.light);
    append(all.shading, d.shading);
    append(all.reconstruction, d.reconstruction);
  }
  return all;
}

namespace {

// Photo-resolution planar layers, premultiplied by the faces' coverage `alpha`.
struct PastedLayers {
  int width = 0, height = 0;
  std::vector<float> alpha, albedo, normal, visibility, shading, reconstruction;
};

}  // namespace

RgbImage planar_rgb(const float* planar, int w, int h) {
  RgbImage img;
  img.width = w;
  img.height = h;
  const size_t plane = static_cast<size_t>(w) * h;
  img.pixels.resize(plane * 3);
  for (size_t p = 0; p < plane; ++p)
    for (int c = 0; c < 3; ++c) img.pixels[p * 3 + c] = planar[c * plane + p];
  return img;
}

namespace {

// One photo-level PNG: the premultiplied layer over the input, or un-premultiplied with alpha.
void write_layer_png(const std::string& path, RgbImage layer, const RgbImage& input,
                     const std::vector<float>& alpha, bool transparent, bool encode_srgb) {
  const size_t plane = alpha.size();
  if (transparent) {
    for (size_t p = 0; p < plane; ++p)
      for (int c = 0; c < 3; ++c) layer.pixels[p * 3 + c] = alpha[p] > 0 ? layer.pixels[p * 3 + c] / alpha[p] : 0.0f;
    write_rgba_png_atomically(path, layer, alpha, encode_srgb);
    return;
  }
  for (size_t p = 0; p < plane; ++p)
    for (int c = 0; c < 3; ++c) {
      const float in = encode_srgb ? input.pixels[p * 3 + c] : linear_to_srgb(input.pixels[p * 3 + c]);
      layer.pixels[p * 3 + c] += (1 - alpha[p]) * in;
    }
  write_png_atomically(path, layer, encode_srgb);
}

std::string faces_json(const std::string& source, const std::vector<FaceCrop>& crops,
                       const std::vector<sh::RgbLight>& photo_lights) {
  std::ostringstream o;
  o << std::setprecision(9) << "{\n  \"source\": \"" << source << "\",\n  \"faces\": [";
  for (size_t k = 0; k < crops.size(); ++k) {
    const FaceCrop& c = crops[k];
    const Similarity2& t = c.alignment.photo_to_crop;
    o << (k ? "," : "") << "\n    {\"folder\": \"face_" << k << "\", \"score\": " << c.face.score
      << ", \"box\": [" << c.face.left << ", " << c.face.top << ", " << c.face.right << ", "
      << c.face.bottom << "], \"found_turned_deg\": " << c.face.rotation_deg
      << ",\n     \"photo_to_crop\": [[" << t.a << ", " << -t.b << ", " << t.tx << "], [" << t.b
      << ", " << t.a << ", " << t.ty << "]], \"crop_size\": " << c.alignment.crop_size
      << ",\n     \"landmarks\": [";
    for (int i = 0; i < kLandmarkCount; ++i)
      o << (i ? ", " : "") << "[" << c.face.landmarks[i].x << ", " << c.face.landmarks[i].y << "]";
    o << "],\n     \"light_photo_frame\": [";
    for (int i = 0; i < sh::kLightCoeffCount; ++i) o << (i ? ", " : "") << photo_lights[k][i];
    o << "]}";
  }
  o << "\n  ]\n}\n";
  return o.str();
}

// Processes one photo; returns false (after printing why) when it has no usable face.
bool infer_photo(const std::string& path, const std::string& folder, FaceDetector& detector,
                 Decomposer& decomposer, Backend& backend, int size, const PhotoInferOptions& options,
                 DetectionSummary& summary) {
  RgbImage photo;
  try {
    photo = read_photo(path);
  } catch (const Error& e) {
    std::cerr << "\nphoto '" << path << "': " << e.what() << "\n";
    summary.add(path, 0, "unreadable");
    return false;
  }
  const std::vector<DetectedFace> faces = detector.detect(photo, options.detection);
  if (faces.empty()) {
    const std::string reason = no_face_reason(photo, options.detection);
    std::cerr << "\nphoto '" << path << "': " << reason << "\n";
    summary.add(path, 0, reason);
    return false;
  }
  summary.add(path, static_cast<int>(faces.size()));
  const int w = photo.width, h = photo.height;
  const size_t plane = static_cast<size_t>(w) * h, crop_plane = static_cast<size_t>(size) * size;
  std::vector<FaceCrop> crops;
  std::vector<float> inputs;
  for (const DetectedFace& f : faces) {
    crops.push_back(crop_face(photo, f, size, options.extend_forehead));
    inputs.insert(inputs.end(), crops.back().rgb.begin(), crops.back().rgb.end());
  }
  const int n = static_cast<int>(crops.size());
  const Decomposition d = decompose_all(decomposer, backend, inputs, n, size, options.batch);

  std::error_code ec;
  fs::create_directories(folder, ec);
  check(!ec, "cannot create output folder '", folder, "': ", ec.message());
  PastedLayers layers;
  layers.alpha.assign(plane, 0.0f);
  layers.albedo.assign(plane * 3, 0.0f);
  layers.normal.assign(plane * 3, 0.0f);
  layers.visibility.assign(plane * 9, 0.0f);
  layers.shading.assign(plane * 3, 0.0f);
  layers.reconstruction.assign(plane * 3, 0.0f);
  std::vector<sh::RgbLight> photo_lights;
  std::vector<RgbImage> sheet_rows;
  for (int k = 0; k < n; ++k) {
    const FaceCrop& c = crops[k];
    const Similarity2& t = c.alignment.photo_to_crop;
    write_decomposition((fs::path(folder) / ("face_" + std::to_string(k))).string(), d, k, inputs, path);
    const PasteRegion region = paste_region(w, h, t, size, c.mask_polygon, options.feather);
    auto slice = [&](const std::vector<float>& all, int channels) {
      return std::vector<float>(all.begin() + k * channels * crop_plane, all.begin() + (k + 1) * channels * crop_plane);
    };
    std::vector<float> normal = slice(d.normal, 3), visibility = slice(d.visibility, 9);
    rotate_normals_to_photo(normal.data(), crop_plane, t);
    rotate_visibility_to_photo(visibility.data(), crop_plane, t);
    const std::vector<float> ones(crop_plane, 1.0f);
    paste_channels(region, ones.data(), 1, layers.alpha.data(), w, h);
    paste_channels(region, slice(d.albedo, 3).data(), 3, layers.albedo.data(), w, h);
    paste_channels(region, normal.data(), 3, layers.normal.data(), w, h);
    paste_channels(region, visibility.data(), 9, layers.visibility.data(), w, h);
    paste_channels(region, slice(d.shading, 3).data(), 3, layers.shading.data(), w, h);
    paste_channels(region, slice(d.reconstruction, 3).data(), 3, layers.reconstruction.data(), w, h);
    sh::RgbLight light;
    for (int i = 0; i < sh::kLightCoeffCount; ++i) light[i] = d.light[static_cast<size_t>(k) * 27 + i];
    photo_lights.push_back(rotate_light_to_photo(light, t));
    if (options.contact_sheet) sheet_rows.push_back(contact_sheet_row(d, k, inputs));
  }

  auto at = [&](const std::string& name) { return (fs::path(folder) / name).string(); };
  const std::string json = faces_json(path, crops, photo_lights);
  write_file_atomically(at("faces.json"), json.data(), json.size());
  write_layer_png(at("albedo.png"), planar_rgb(layers.albedo.data(), w, h), photo, layers.alpha, options.transparent, true);
  write_layer_png(at("shading.png"), planar_rgb(layers.shading.data(), w, h), photo, layers.alpha, options.transparent, true);
  write_layer_png(at("reconstruction.png"), planar_rgb(layers.reconstruction.data(), w, h), photo, layers.alpha, options.transparent, true);
  RgbImage normal_png = planar_rgb(layers.normal.data(), w, h), visibility_png = normal_png;
  const float unoccluded = static_cast<float>(2.0 * std::sqrt(kPi));
  for (size_t p = 0; p < plane; ++p)
    for (int c = 0; c < 3; ++c) {
      normal_png.pixels[p * 3 + c] = 0.5f * (normal_png.pixels[p * 3 + c] + layers.alpha[p]);  // premultiplied (n + 1) / 2
      visibility_png.pixels[p * 3 + c] = layers.visibility[p] / unoccluded;
    }
  write_layer_png(at("normal.png"), normal_png, photo, layers.alpha, options.transparent, false);
  write_layer_png(at("visibility.png"), visibility_png, photo, layers.alpha, options.transparent, false);

  std::vector<std::string> names = {"R", "G", "B", "A", "albedo.R", "albedo.G", "albedo.B",
                                    "normal.X", "normal.Y", "normal.Z"};
  for (int i = 0; i < 9; ++i) names.push_back("visibility." + std::to_string(i));
  for (const char* layer : {"shading", "reconstruction"})
    for (const char* c : {"R", "G", "B"}) names.push_back(std::string(layer) + "." + c);
  LayeredImage exr(w, h, names);
  for (size_t p = 0; p < plane; ++p)
    for (int c = 0; c < 3; ++c) exr.plane(c)[p] = photo.pixels[p * 3 + c];
  std::copy(layers.alpha.begin(), layers.alpha.end(), exr.plane(3));
  std::copy(layers.albedo.begin(), layers.albedo.end(), exr.plane(4));
  std::copy(layers.normal.begin(), layers.normal.end(), exr.plane(7));
  std::copy(layers.visibility.begin(), layers.visibility.end(), exr.plane(10));
  std::copy(layers.shading.begin(), layers.shading.end(), exr.plane(19));
  std::copy(layers.reconstruction.begin(), layers.reconstruction.end(), exr.plane(22));
  exr.set_metadata("facetool:source", path);
  exr.set_metadata("facetool:faces", std::to_string(n));
  write_exr_atomically(at("photo.exr"), exr);

  if (options.contact_sheet) {
    const int width = sheet_rows[0].width;
    RgbImage annotated = resize_to_width(photo, width);
    for (const FaceCrop& c : crops) draw_face(annotated, c.face, static_cast<double>(width) / w);
    sheet_rows.insert(sheet_rows.begin(), annotated);
    write_png_atomically(at("contact_sheet.png"), stack_rows(sheet_rows));
  }
  return true;
}

}  // namespace

void add_photo_detection_options(po::options_description& options) {
  options.add_options()
      ("detector", po::value<std::string>()->default_value("auto"), "face detector: hog, cnn, or auto (HOG, and dlib's CNN when HOG finds no face; docs/photos.md)")
      ("cnn-model", po::value<std::string>()->default_value(kDefaultCnnFaceModel), "dlib's CNN face detector model (mmod_human_face_detector.dat; scripts/install-dependencies.sh)")
      ("max-faces", po::value<int>()->default_value(0), "keep at most this many faces per photo, best detection score first (0: all)")
      ("min-face-size", po::value<double>()->default_value(0), "smallest face to find, photo pixels (0: max(80, shorter side / 8)); a smaller value never finds fewer faces")
      ("min-score", po::value<double>()->default_value(0.25), "HOG detection score (margin) below which a box is not a face")
      ("min-cnn-score", po::value<double>()->default_value(0.0), "CNN detection score below which a box is not a face")
      ("pad", po::value<double>()->default_value(0.25), "before detection, pad the photo on every side by this fraction of its shorter side, in its mean colour, so faces filling the photo or cut by its edge are found")
      ("landmark-model", po::value<std::string>()->default_value(kDefaultLandmarkModel),
       "dlib 68-point shape predictor (Debian libdlib-data; trained on iBUG 300-W: research use only, no commercial use)")
      ("forehead", "extend the landmarks' convex hull over the forehead (docs/photos.md)");
}

void add_photo_infer_options(po::options_description& options) {
  add_photo_detection_options(options);
  options.add_options()
      ("feather", po::value<double>()->default_value(3.0), "width of the blend at the mask's edge, crop pixels")
      ("transparent", "photo-level PNGs transparent outside the faces (default: the input photo there)");
}

std::vector<OptionRange> photo_option_ranges() {
  return {{"max-faces", 0, 10000},
          {"min-face-size", 0, 1e6},
          {"min-score", -10, 10},
          {"min-cnn-score", -10, 10},
          {"pad", 0, 2},
          {"feather", 0, 256}};
}

PhotoInferOptions photo_options_from(const po::variables_map& values) {
  PhotoInferOptions o;
  o.detection.max_faces = values["max-faces"].as<int>();
  o.detection.min_face_size = values["min-face-size"].as<double>();
  o.detection.score_threshold = values["min-score"].as<double>();
  o.landmark_model = values["landmark-model"].as<std::string>();
  o.detection.detector = parse_detector_choice(values["detector"].as<std::string>());
  o.cnn_model = values["cnn-model"].as<std::string>();
  o.detection.cnn_score_threshold = values["min-cnn-score"].as<double>();
  o.detection.padding = values["pad"].as<double>();
  o.extend_forehead = values.count("forehead") > 0;
  if (values.count("feather")) o.feather = values["feather"].as<double>();
  o.transparent = values.count("transparent") > 0;
  if (o.detection.max_faces < 0) fail("--max-faces must be 0 (all) or more");
  if (o.detection.min_face_size < 0) fail("--min-face-size must be 0 (automatic) or more");
  if (o.feather < 0) fail("--feather must be 0 or more");
  return o;
}

std::vector<std::string> expand_photo_inputs(const std::vector<std::string>& inputs) {
  std::vector<std::string> photos;
  for (const std::string& input : inputs) {
    if (fs::is_directory(input)) {
      std::vector<std::string> found;
      for (const fs::directory_entry& e : fs::directory_iterator(input))
        if (e.is_regular_file() && is_photo_file(e.path())) found.push_back(e.path().string());
      std::sort(found.begin(), found.end());
      check(!found.empty(), "folder '", input, "' holds no photos (png, jpg, jpeg, tif, tiff, bmp, webp, exr, hdr, pgm, ppm)");
      photos.insert(photos.end(), found.begin(), found.end());
    } else {
      check(fs::is_regular_file(input), "input photo '", input, "' does not exist or is not a file or folder");
      photos.push_back(input);
    }
  }
  return photos;
}

int infer_photos(const std::vector<std::string>& photos, const std::string& out_dir,
                 Decomposer& decomposer, Backend& backend, int crop_size,
                 const PhotoInferOptions& options) {
  FaceDetector detector(options.landmark_model, options.cnn_model);
  detector.prepare(options.detection.detector);
  DetectionSummary summary;
  std::map<std::string, int> seen;
  int failed = 0;
  ProgressBar progress("infer", static_cast<int64_t>(photos.size()), "photos");
  for (const std::string& path : photos) {
    std::string stem = fs::path(path).stem().string();
    const int k = ++seen[stem];
    if (k > 1) stem += "_" + std::to_string(k);
    if (!infer_photo(path, (fs::path(out_dir) / stem).string(), detector, decomposer, backend,
                     crop_size, options, summary))
      ++failed;
    progress.advance();
  }
  progress.finish();
  summary.print(std::cerr);
  return failed;
}

}  // namespace facetool
