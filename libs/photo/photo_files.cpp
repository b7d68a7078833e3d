// The files of `facetool infer` on photos: per face, per photo, and the loop over photos.
#include "libs/photo/photo_files.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <filesystem>
#include <functional>
#include <future>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <system_error>
#include <tuple>
#include <utility>

#include "libs/face/detection_summary.h"
#include "libs/face/landmark_drawing.h"
#include "libs/face/photo_reader.h"
#include "libs/face/rgba_png.h"
#include "libs/fit/photo_fit.h"
#include "libs/io/exr_io.h"
#include "libs/io/face_folders.h"
#include "libs/io/image_io.h"
#include "libs/io/png_encoding.h"
#include "libs/photo/decomposition_files.h"
#include "core/util/atomic_file.h"
#include "core/util/background_worker.h"
#include "core/util/error.h"
#include "core/util/math_constants.h"
#include "core/util/memory_budget.h"
#include "core/util/parallel_for.h"
#include "core/util/progress_bar.h"
#include "core/util/stage_timer.h"

namespace fs = std::filesystem;

namespace facetool {
namespace {

// The photo's sRGB bytes (linear_to_srgb8) where alpha is 0: what each layer picture shows where
// only the photo shows, made once for the five of them; 0 under the faces (not read there).
std::vector<uint8_t> photo_srgb8(const RgbImage& input, const std::vector<float>& alpha) {
  std::vector<uint8_t> bytes(input.pixels.size(), 0);
  for (size_t p = 0; p < alpha.size(); ++p)
    if (alpha[p] == 0)
      for (size_t i = p * 3; i < p * 3 + 3; ++i) bytes[i] = linear_to_srgb8(input.pixels[i]);
  return bytes;
}

// One photo-level PNG's bytes: the premultiplied layer over the photo (`input`, linear RGB; its
// sRGB bytes `input_srgb8`), or un-premultiplied with alpha. A linear layer (encode_srgb) is
// composited in linear values, a data layer over the photo's sRGB encoding. Where only the photo
// shows (alpha 0, layer 0) both give the photo's own sRGB byte (a data layer's linear_to_srgb(x)
// rounds to linear_to_srgb8(x)), taken from input_srgb8 (photo_srgb8: set where alpha is 0).
std::vector<unsigned char> encode_layer_png(const std::string& path, RgbImage layer, const RgbImage& input,
                                            const std::vector<uint8_t>& input_srgb8, const std::vector<float>& alpha,
                                            bool transparent, bool encode_srgb) {
  const size_t plane = alpha.size();
  if (transparent) {
    for (size_t p = 0; p < plane; ++p)
      for (int c = 0; c < 3; ++c) layer.pixels[p * 3 + c] = alpha[p] > 0 ? layer.pixels[p * 3 + c] / alpha[p] : 0.0f;
    return encode_rgba_png(path, layer, alpha, encode_srgb);
  }
  StageTimer timer("encode");  // compositing and the 8-bit conversion; encode_png8 compresses
  std::vector<uint8_t> bytes(plane * 3);
  for (size_t p = 0; p < plane; ++p) {
    const float a = alpha[p];
    for (size_t i = p * 3; i < p * 3 + 3; ++i) {
      const float v = layer.pixels[i], x = input.pixels[i];
      if (a == 0 && v == 0)
        bytes[i] = input_srgb8[i];
      else if (encode_srgb)
        bytes[i] = linear_to_srgb8(v + (1 - a) * x);
      else  // where the layer covers the photo (a = 1) its sRGB value is multiplied by 0: not computed
        bytes[i] = unit_to_byte(a == 1 ? v : v + (1 - a) * linear_to_srgb(x));
    }
  }
  return encode_png8(path, layer.width, layer.height, 3, bytes.data());
}

// One of the photo-level layer pictures ("albedo", "shading", "reconstruction": linear colours;
// "normal": premultiplied (n + 1) / 2; "visibility": the ambient term over the open sphere's).
std::vector<unsigned char> layer_png(const std::string& path, const std::string& layer, const DecomposedPhoto& photo,
                                     const std::vector<uint8_t>& input_srgb8, bool transparent) {
  const PhotoLayers& layers = photo.layers;
  const std::vector<float>& alpha = layers.alpha;
  const int w = photo.photo.width, h = photo.photo.height;
  const size_t plane = alpha.size();
  if (layer == "normal") {
    RgbImage normal_png = rgb_from_planar(layers.normal.data(), w, h);
    for (size_t p = 0; p < plane; ++p)
      for (int c = 0; c < 3; ++c)  // premultiplied (n + 1) / 2
        normal_png.pixels[p * 3 + c] = 0.5f * (normal_png.pixels[p * 3 + c] + alpha[p]);
    return encode_layer_png(path, std::move(normal_png), photo.photo, input_srgb8, alpha, transparent, false);
  }
  if (layer == "visibility") {
    RgbImage visibility_png;
    visibility_png.width = w;
    visibility_png.height = h;
    visibility_png.pixels.resize(plane * 3);
    const float unoccluded = static_cast<float>(2.0 * std::sqrt(kPi));
    for (size_t p = 0; p < plane; ++p)
      for (int c = 0; c < 3; ++c) visibility_png.pixels[p * 3 + c] = layers.visibility[p] / unoccluded;
    return encode_layer_png(path, std::move(visibility_png), photo.photo, input_srgb8, alpha, transparent, false);
  }
  const std::vector<float>* planar = layer == "albedo" ? &layers.albedo
                                     : layer == "shading" ? &layers.shading
                                     : layer == "reconstruction" ? &layers.reconstruction : nullptr;
  check(planar != nullptr, "photo files: no layer picture '", layer, "'");
  return encode_layer_png(path, rgb_from_planar(planar->data(), w, h), photo.photo, input_srgb8, alpha, transparent, true);
}

// A file to encode: its path and the function that makes its bytes.
struct EncodeJob {
  std::string path;
  std::function<std::vector<unsigned char>()> encode;
};

// Encodes the jobs on the calling thread and, when facetool may use more than one thread, one
// more (the writer runs beside the next photo's detection and network, which leave a core idle
// part of the time), then writes the files in order on the calling thread, inside its WriteBatch.
// The first job's failure is rethrown after both threads stop; nothing is written then.
void encode_and_write(const std::vector<EncodeJob>& jobs) {
  std::vector<std::vector<unsigned char>> bytes(jobs.size());
  std::atomic<size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&] {
    for (size_t i; !failed && (i = next++) < jobs.size();) {
      try {
        bytes[i] = jobs[i].encode();
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        failed = true;
      }
    }
  };
  std::future<void> helper;
  if (parallel_thread_count() > 1 && jobs.size() > 1) {
    try {
      helper = std::async(std::launch::async, work);
    } catch (const std::system_error&) {  // no thread to be had (a process limit): one is enough
    }
  }
  work();
  if (helper.valid()) helper.get();
  if (error) std::rethrow_exception(error);
  for (size_t i = 0; i < jobs.size(); ++i) write_file_atomically(jobs[i].path, bytes[i].data(), bytes[i].size());
}

// The light solve's answer for one face (libs/light/light_from_shading.h), its direction turned to
// the photo's frame (the band 1 of the photo-frame light, which is the solved light's direction).
void light_solve_json(std::ostream& o, const DistantLight& solve, const sh::RgbLight& photo_light) {
  double d[3] = {0, 0, 0};
  for (int c = 0; c < 3; ++c) {
    d[0] += photo_light[c * 9 + 3];
    d[1] += photo_light[c * 9 + 1];
    d[2] += photo_light[c * 9 + 2];
  }
  const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (length > 0)
    for (double& v : d) v /= length;
  o << ",\n     \"light_solve\": {\"direction_photo_frame\": [" << d[0] << ", " << d[1] << ", " << d[2]
    << "], \"ambient\": [" << solve.ambient[0] << ", " << solve.ambient[1] << ", " << solve.ambient[2]
    << "], \"intensity\": [" << solve.intensity[0] << ", " << solve.intensity[1] << ", " << solve.intensity[2]
    << "], \"relative_residual\": " << solve.relative_residual << ", \"pixels\": " << solve.pixels
    << ", \"warning\": \"" << solve.warning << "\"}";
}

std::string faces_json(const std::string& source, const std::vector<FaceCrop>& crops,
                       const std::vector<sh::RgbLight>& photo_lights, const std::vector<DistantLight>& solves,
                       const PhotoInferOptions& options) {
  std::ostringstream o;
  // face_region and feather: the paste-back mask as used (--face-region resolved, --feather), for view.
  o << std::setprecision(9) << "{\n  \"source\": \"" << source << "\",\n  \"face_region\": \""
    << (options.extends_forehead() ? "forehead" : "hull") << "\", \"feather\": " << options.feather
    << ",\n  \"faces\": [";
  for (size_t k = 0; k < crops.size(); ++k) {
    const FaceCrop& c = crops[k];
    const Similarity2& t = c.alignment.photo_to_crop;
    o << (k ? "," : "") << "\n    {\"folder\": \"face_" << k << "\", \"score\": " << c.face.score
      << ", \"box\": [" << c.face.left << ", " << c.face.top << ", " << c.face.right << ", "
      << c.face.bottom << "], \"found_by\": \"" << c.face.found_by() << "\", \"found_turned_deg\": "
      << c.face.rotation_deg << ", \"padding_px\": " << c.face.padding << ", \"landmark_disagreement\": "
      << c.face.landmark_disagreement << ", \"landmarks_retried\": " << (c.face.landmarks_retried ? "true" : "false")
      << ", \"brightened\": " << (c.face.brightened ? "true" : "false") << ", \"landmark_box\": \"" << c.face.landmark_box << "\""
      << ",\n     \"photo_to_crop\": [[" << t.a << ", " << -t.b << ", " << t.tx << "], [" << t.b
      << ", " << t.a << ", " << t.ty << "]], \"crop_size\": " << c.alignment.crop_size
      << ",\n     \"landmarks\": [";
    for (int i = 0; i < kLandmarkCount; ++i)
      o << (i ? ", " : "") << "[" << c.face.landmarks[i].x << ", " << c.face.landmarks[i].y << "]";
    o << "],\n     \"light_photo_frame\": [";
    for (int i = 0; i < sh::kLightCoeffCount; ++i) o << (i ? ", " : "") << photo_lights[k][i];
    o << "]";
    if (k < solves.size() && solves[k].solved) light_solve_json(o, solves[k], photo_lights[k]);
    o << "}";
  }
  o << "\n  ]\n}\n";
  return o.str();
}

}  // namespace

std::vector<unsigned char> encode_photo_layer_png(const DecomposedPhoto& photo, const std::string& layer) {
  const std::vector<uint8_t> input_srgb8 = photo_srgb8(photo.photo, photo.layers.alpha);
  return layer_png(layer + ".png", layer, photo, input_srgb8, false);
}

void write_photo_files(const std::string& folder, const DecomposedPhoto& photo, const PhotoInferOptions& options) {
  const PhotoOutputs& outputs = options.outputs;
  const Decomposition& d = photo.decomposition;
  const PhotoLayers& layers = photo.layers;
  const int w = photo.photo.width, h = photo.photo.height, n = d.count;
  const size_t plane = static_cast<size_t>(w) * h;
  const PhotoLayerSet needed = outputs.layers();
  for (PhotoLayer layer : all_photo_layers())
    check(!needed.has(layer) || layers.made.has(layer), "writing the files of '", photo.path, "': the ",
          photo_layer_name(layer), " layer was not pasted back (PhotoInferOptions::layers lacks it)");
  std::error_code ec;
  fs::create_directories(folder, ec);
  check(!ec, "cannot create output folder '", folder, "': ", ec.message());
  std::vector<float> inputs;
  const bool sheet = outputs.has(PhotoOutput::kContactSheet);
  if (sheet || outputs.has(PhotoOutput::kFaceFolders))
    for (const FaceCrop& c : photo.crops) inputs.insert(inputs.end(), c.rgb.begin(), c.rgb.end());
  std::vector<RgbImage> sheet_rows;
  for (int k = 0; k < n; ++k) {
    if (outputs.has(PhotoOutput::kFaceFolders)) write_decomposition(face_folder_name(folder, k), d, k, inputs, photo.path);
    if (sheet) sheet_rows.push_back(contact_sheet_row(d, k, inputs));
  }

  auto at = [&](const std::string& name) { return (fs::path(folder) / name).string(); };
  // faces.json whatever the outputs: where the faces are, and their lights.
  const std::string json = faces_json(photo.path, photo.crops, photo.photo_lights, photo.decomposition.light_solve, options);
  write_file_atomically(at("faces.json"), json.data(), json.size());
  // The photo-level pictures asked for, each made and encoded by a job (the largest first), then written.
  const RgbImage& input = photo.photo;
  const std::vector<float>& alpha = layers.alpha;
  const bool any_png = outputs.has(PhotoOutput::kAlbedo) || outputs.has(PhotoOutput::kNormal) ||
                       outputs.has(PhotoOutput::kVisibility) || outputs.has(PhotoOutput::kShading) ||
                       outputs.has(PhotoOutput::kReconstruction);
  const std::vector<uint8_t> input_srgb8 =
      options.transparent || !any_png ? std::vector<uint8_t>() : photo_srgb8(input, alpha);
  const bool transparent = options.transparent;
  std::vector<EncodeJob> jobs;
  if (outputs.has(PhotoOutput::kExr))
    jobs.push_back({at("photo.exr"), [&] {
      // The photo and its alpha as 32-bit floats (the input kept exactly); the layers the network
      // made as 16-bit halves (docs/photos.md: half the file, and faster to write). Read where
      // they lie: no planar copy of the 25 channels.
      std::vector<ExrChannel> channels;
      for (int c = 0; c < 3; ++c) channels.push_back({std::string(1, "RGB"[c]), input.pixels.data() + c, 3, false});
      channels.push_back({"A", alpha.data(), 1, false});
      auto add = [&](const std::string& layer, const char* components, const std::vector<float>& planes) {
        for (size_t c = 0; components[c]; ++c)
          channels.push_back({layer + "." + components[c], planes.data() + c * plane, 1, true});
      };
      add("albedo", "RGB", layers.albedo);
      add("normal", "XYZ", layers.normal);
      add("visibility", "012345678", layers.visibility);
      add("shading", "RGB", layers.shading);
      add("reconstruction", "RGB", layers.reconstruction);
      return encode_exr(at("photo.exr"), w, h, channels,
                        {{"facetool:source", photo.path}, {"facetool:faces", std::to_string(n)}});
    }});
  const std::pair<PhotoOutput, const char*> layer_pngs[] = {{PhotoOutput::kAlbedo, "albedo"},
                                                           {PhotoOutput::kShading, "shading"},
                                                           {PhotoOutput::kReconstruction, "reconstruction"},
                                                           {PhotoOutput::kNormal, "normal"},
                                                           {PhotoOutput::kVisibility, "visibility"}};
  for (const auto& [output, layer] : layer_pngs) {
    if (!outputs.has(output)) continue;
    const std::string path = at(std::string(layer) + ".png");
    jobs.push_back({path, [&, layer = layer, path] { return layer_png(path, layer, photo, input_srgb8, transparent); }});
  }
  if (sheet)
    jobs.push_back({at("contact_sheet.png"), [&] {
      const int width = sheet_rows[0].width;
      std::vector<RgbImage> rows = sheet_rows;
      RgbImage annotated = resize_to_width(input, width);
      for (const FaceCrop& c : photo.crops) draw_face(annotated, c.face, static_cast<double>(width) / w);
      rows.insert(rows.begin(), annotated);
      return encode_png(at("contact_sheet.png"), stack_rows(rows));
    }});
  encode_and_write(jobs);

  // face_<k>/ folders of an earlier run of this photo that found more faces: its results are
  // replaced by this run's, which has fewer faces (faces.json lists them).
  // (Without face-folders in the outputs, the face folders of an earlier run are left alone, as
  // every other file not asked for is.)
  if (outputs.has(PhotoOutput::kFaceFolders)) remove_stale_face_folders(folder, n);
  if (options.with_fit) {  // docs/fit.md: the fit's products beside the network's
    std::vector<DetectedFace> faces;
    for (const FaceCrop& c : photo.crops) faces.push_back(c.face);
    const std::vector<DetectedFace> ordered = order_faces_by_size(faces);
    options.with_fit->write(at("fit"), photo.photo, ordered, options.with_fit->fit(photo.photo, ordered), photo.path);
  }
}

int infer_photos(const std::vector<std::string>& photos, const std::vector<std::string>& folders,
                 const std::string& out_dir, PhotoDecomposer& decomposer, const PhotoInferOptions& options) {
  check(photos.size() == folders.size(), "infer: ", photos.size(), " photos for ", folders.size(), " folder names");
  std::atomic<int> failed{0};
  DetectionSummary summary;
  ProgressBar progress("infer", static_cast<int64_t>(photos.size()), "photos");
  // Photos whose faces are found wait in a group until it holds options.batch faces or
  // kGroupPixels pixels, or the writer is idle; the network then runs on all their faces in one
  // batch. A photo's faces are pasted back and its files encoded and written on the worker while
  // the next photos are decoded, detected and run through the network; its files land together
  // (WriteBatch: one flush per photo, all of them or none). A failure to write them (a full disk)
  // ends the run at the next photo handed over.
  constexpr double kGroupPixels = 2e6;
  // The worker holds up to a group's worth of photos (at least one photo; a photo weighs its
  // pixels, at least kGroupPixels / batch), so that the next group is found while it writes.
  BackgroundWorker writer(kGroupPixels);
  std::vector<FoundPhoto> group;
  std::vector<std::string> group_folders;
  int group_faces = 0;
  double group_pixels = 0;
  auto run_group = [&] {
    if (group.empty()) return;
    std::vector<std::string> paths, folders_now = std::move(group_folders);
    for (const FoundPhoto& f : group) paths.push_back(f.path);
    std::vector<FoundPhoto> found = std::move(group);
    std::vector<Decomposition> faces;
    std::string failure;
    try {
      faces = decomposer.decompose_faces(found);
    } catch (const std::bad_alloc&) {
      failure = out_of_memory("running the network on the faces of these photos", 0).what();
    } catch (const Error& e) {
      failure = e.what();
    }
    group.clear();
    group_folders.clear();
    group_faces = 0;
    group_pixels = 0;
    if (!failure.empty()) {
      for (const std::string& path : paths) {
        std::cerr << "\nphoto '" << path << "': " << failure << "\n";
        ++failed;
        progress.advance();
      }
      return;
    }
    for (size_t i = 0; i < found.size(); ++i) {
      auto job = std::make_shared<std::pair<FoundPhoto, Decomposition>>(std::move(found[i]), std::move(faces[i]));
      const double weight = std::max(static_cast<double>(job->first.photo.width) * job->first.photo.height,
                                     kGroupPixels / options.batch);
      const std::string folder = (fs::path(out_dir) / folders_now[i]).string(), path = paths[i];
      writer.submit(
          [job, folder, path, &decomposer, &options, &failed] {
            DecomposedPhoto photo;
            try {
              // The paste-back here, on the writer's thread alone: the network's next batch
              // keeps both of the pool's threads meanwhile.
              InlineParallelScope here;
              photo = decomposer.assemble(std::move(job->first), job->second);
            } catch (const std::bad_alloc&) {
              std::cerr << "\nphoto '" << path << "': "
                        << out_of_memory("pasting the faces back into photo '" + path + "'", 0).what() << "\n";
              ++failed;
              return;
            } catch (const Error& e) {
              std::cerr << "\nphoto '" << path << "': " << e.what() << "\n";
              ++failed;
              return;
            }
            try {
              WriteBatch batch;
              write_photo_files(folder, photo, options);
              batch.commit();
              const std::vector<DistantLight>& solves = photo.decomposition.light_solve;
              for (size_t k = 0; k < solves.size(); ++k)
                if (!solves[k].warning.empty())
                  std::cerr << "\nphoto '" << path << "', face " << k << ": " << solves[k].warning << "\n";
            } catch (const std::bad_alloc&) {
              std::cerr << "\nphoto '" << path << "': "
                        << out_of_memory("writing the results of photo '" + path + "'", 0).what() << "\n";
              ++failed;
            }
          },
          weight);
      progress.advance();
    }
  };
  for (size_t k = 0; k < photos.size(); ++k) {
    const std::string& path = photos[k];
    // A photo that cannot be read, has no face or is too large for the memory left is reported
    // and skipped.
    try {
      RgbImage image;
      try {
        image = read_photo(path);
      } catch (const OutOfMemory&) {
        summary.add(path, 0, "out of memory");
        throw;
      } catch (const Error& e) {
        summary.add(path, 0, "unreadable");
        fail("photo '", path, "': ", e.what());
      }
      try {
        group.push_back(decomposer.find(std::move(image), path));
      } catch (const NoFaceError& e) {
        summary.add(path, 0, e.reason());
        throw;
      }
      group_folders.push_back(folders[k]);
      summary.add(path, static_cast<int>(group.back().crops.size()));
      group_faces += static_cast<int>(group.back().crops.size());
      group_pixels += static_cast<double>(group.back().photo.width) * group.back().photo.height;
    } catch (const std::bad_alloc&) {
      std::cerr << "\nphoto '" << path << "': " << out_of_memory("processing photo '" + path + "'", 0).what() << "\n";
      ++failed;
      progress.advance();
      continue;
    } catch (const Error& e) {
      std::cerr << "\n" << e.what() << "\n";
      ++failed;
      progress.advance();
      continue;
    }
    // A group also goes as soon as the writer has nothing to do, so that it never waits for a
    // group to fill (the batches are as large as the writer's pace allows).
    if (group_faces >= options.batch || group_pixels >= kGroupPixels || writer.idle()) run_group();
  }
  run_group();
  writer.finish();
  progress.finish();
  summary.print(std::cerr);
  return failed.load();
}

}  // namespace facetool
