// Reading one photo's infer folder back for the page: photo.exr, faces.json, face_K/*.exr, PNGs.
#include "libs/view/view_inputs.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/sh/sh_rotation.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "libs/face/face_mask.h"
#include "libs/face/frame_rotation.h"
#include "libs/face/paste_back.h"
#include "libs/io/exr_io.h"

namespace fs = std::filesystem;

namespace facetool::view {
namespace {

std::string at(const std::string& folder, const std::string& name) { return (fs::path(folder) / name).string(); }

// A file infer writes in every photo folder; its absence means this is not one (or a damaged one).
void require_file(const std::string& folder, const std::string& name) {
  const std::string path = at(folder, name);
  check(fs::is_regular_file(path), "'", folder, "' has no ", name, ": it is not a photo folder of `facetool infer` ",
        "(or one of its files was removed); give the folder infer wrote for one photo (OUT/<photo name>), ",
        "or run `facetool infer PHOTO -o OUT` again");
}

const nlohmann::json& field(const nlohmann::json& object, const char* key, const std::string& file) {
  check(object.is_object() && object.contains(key), file, ": no \"", key, "\"; the file is damaged, run infer again");
  return object.at(key);
}

double number(const nlohmann::json& value, const std::string& file) {
  check(value.is_number() && std::isfinite(value.get<double>()), file, ": a value is not a finite number; ",
        "the file is damaged, run infer again");
  return value.get<double>();
}

// The channels `names` of an EXR of size `size` x `size`, planar, appended to `planes`.
void append_exr_planes(const std::string& path, const std::vector<std::string>& names, int size,
                       std::vector<float>& planes) {
  check(fs::is_regular_file(path), "'", path, "' is missing: the face's layers are incomplete; run infer again");
  check_regular_input_file(path, kMaxImageFileBytes, "face layer");
  const LayeredImage image = read_exr(path);
  check(image.width == size && image.height == size, "'", path, "' is ", image.width, "x", image.height,
        " but faces.json gives crop_size ", size, "; the folder mixes runs, run infer again");
  for (const std::string& name : names) {
    const float* plane = image.plane(image.require_channel(name, path));
    for (size_t p = 0; p < image.plane_size(); ++p)
      check(std::isfinite(plane[p]), "'", path, "' channel ", name, " holds a value that is not finite; run infer again");
    planes.insert(planes.end(), plane, plane + image.plane_size());
  }
}

// The coverage infer stores (photo.exr's A): every face's region pasted over 0 in order.
std::vector<float> coverage(const std::vector<PasteRegion>& regions, int w, int h) {
  std::vector<float> alpha(static_cast<size_t>(w) * h, 0.0f);
  for (const PasteRegion& r : regions) {
    const std::vector<float> ones(static_cast<size_t>(r.crop_size) * r.crop_size, 1.0f);
    paste_channels(r, ones.data(), 1, alpha.data(), w, h);
  }
  return alpha;
}

double largest_difference(const std::vector<float>& a, const std::vector<float>& b) {
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(static_cast<double>(a[i]) - b[i]));
  return worst;
}

std::vector<Point2> crop_polygon(const ViewFace& face, bool forehead) {
  check(face.landmarks.size() == static_cast<size_t>(kLandmarkCount), "faces.json: a face has ", face.landmarks.size(),
        " landmarks, not ", kLandmarkCount, "; run infer again");
  Landmarks68 crop{};
  for (int i = 0; i < kLandmarkCount; ++i) crop[i] = face.photo_to_crop.apply(face.landmarks[i]);
  return face_mask_polygon(crop, forehead);
}

}  // namespace

double mask_mismatch(const ViewPhoto& photo, bool forehead) {
  std::vector<PasteRegion> regions;
  for (const ViewFace& face : photo.faces)
    regions.push_back(paste_region(photo.width, photo.height, face.photo_to_crop, face.crop_size,
                                   crop_polygon(face, forehead), photo.feather));
  return largest_difference(coverage(regions, photo.width, photo.height), photo.alpha);
}

void set_face_geometry(ViewPhoto& photo, bool forehead) {
  photo.mask_shape = forehead ? "forehead" : "hull";
  for (ViewFace& face : photo.faces) {
    // A light's coefficients from the photo's frame into the crop's: relight turns the new light
    // by the inverse of the crop-to-photo rotation; its 9x9 matrix, column i the turned basis light i.
    const sh::Mat3 to_photo = crop_to_photo_rotation(face.photo_to_crop);
    sh::Mat3 to_crop{};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) to_crop[i][j] = to_photo[j][i];
    for (int i = 0; i < 9; ++i) {
      sh::RgbLight unit{};
      unit[i] = 1.0;
      const sh::RgbLight turned = sh::rotate_light(unit, to_crop);
      for (int r = 0; r < 9; ++r) face.photo_to_crop_sh[r * 9 + i] = turned[r];
    }
    const std::vector<Point2> polygon = crop_polygon(face, forehead);
    const PasteRegion region = paste_region(photo.width, photo.height, face.photo_to_crop, face.crop_size, polygon, 0.0);
    face.region = {region.x0, region.y0, region.width, region.height};
    face.mask_lines.clear();
    const ConvexInterior interior(polygon);  // the mask's own edges
    for (const ConvexInterior::Line& line : interior.lines()) face.mask_lines.push_back({line.nx, line.ny, line.c});
  }
}

const std::vector<std::string>& view_layer_names() {
  static const std::vector<std::string> names = {"albedo", "normal", "shading", "visibility", "reconstruction"};
  return names;
}

ViewPhoto read_view_photo(const std::string& folder, const ViewOptions& options) {
  check(fs::is_directory(folder), "'", folder, "' is not a folder; give the folder `facetool infer` wrote for one photo");
  require_file(folder, "faces.json");
  require_file(folder, "photo.exr");
  ViewPhoto out;
  out.name = fs::path(folder).lexically_normal().filename().string();
  if (out.name.empty() || out.name == ".") out.name = fs::absolute(folder).lexically_normal().parent_path().filename().string();
  out.feather = options.feather;

  const std::string exr_path = at(folder, "photo.exr");
  const LayeredImage header = read_exr_header(exr_path);
  check(header.width >= 16 && header.height >= 16, "'", exr_path, "' is ", header.width, "x", header.height,
        ": too small to hold a face (at least 16x16); it is not a photo infer decomposed");
  check(header.width <= options.max_side && header.height <= options.max_side, "'", exr_path, "' is ", header.width,
        "x", header.height, ", larger than the page's limit of ", options.max_side, " pixels a side (browsers' WebGL ",
        "textures); give a downscaled photo to infer, or raise the limit with --max-side (up to 8192)");
  for (const char* name : {"R", "G", "B", "A"})
    check(header.find_channel(name) >= 0, "'", exr_path, "' has no channel ", name, ": it is not infer's photo.exr; run infer again");
  for (const std::string& layer : view_layer_names()) require_file(folder, layer + ".png");

  const std::string json_path = at(folder, "faces.json");
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(read_regular_input_file(json_path, kMaxTextFileBytes, "faces.json"));
  } catch (const nlohmann::json::exception& e) {
    fail("'", json_path, "' is not valid JSON (", e.what(), "); run infer again");
  }
  if (json.contains("source") && json["source"].is_string()) out.source = json["source"].get<std::string>();
  const nlohmann::json& faces = field(json, "faces", json_path);
  check(faces.is_array() && !faces.empty(), "'", json_path, "' lists no face; infer writes a folder only for a photo with a face");
  check(faces.size() <= static_cast<size_t>(kMaxViewFaces), "'", json_path, "' lists ", faces.size(),
        " faces; the page relights at most ", kMaxViewFaces, " (one WebGL pass)");

  {
    const LayeredImage photo = read_exr(exr_path);
    out.width = photo.width;
    out.height = photo.height;
    const size_t plane = photo.plane_size();
    out.photo.resize(plane * 3);
    for (int c = 0; c < 3; ++c) {
      const float* p = photo.plane(photo.require_channel(std::string(1, "RGB"[c]), exr_path));
      for (size_t i = 0; i < plane; ++i) out.photo[i * 3 + c] = p[i];
    }
    const float* a = photo.plane(photo.require_channel("A", exr_path));
    out.alpha.assign(a, a + plane);
  }

  for (const nlohmann::json& f : faces) {
    ViewFace face;
    face.folder = field(f, "folder", json_path).get<std::string>();
    check(face.folder.find('/') == std::string::npos && face.folder.find("..") == std::string::npos,
          "'", json_path, "' names a face folder outside the photo's folder; run infer again");
    face.crop_size = static_cast<int>(number(field(f, "crop_size", json_path), json_path));
    check(face.crop_size >= 8 && face.crop_size <= 1024, "'", json_path, "': crop_size ", face.crop_size, " is out of range");
    const nlohmann::json& t = field(f, "photo_to_crop", json_path);
    check(t.is_array() && t.size() == 2 && t[0].size() == 3 && t[1].size() == 3, "'", json_path,
          "': photo_to_crop is not a 2x3 matrix; run infer again");
    face.photo_to_crop.a = number(t[0][0], json_path);
    face.photo_to_crop.b = number(t[1][0], json_path);
    face.photo_to_crop.tx = number(t[0][2], json_path);
    face.photo_to_crop.ty = number(t[1][2], json_path);
    for (const nlohmann::json& p : field(f, "landmarks", json_path))
      face.landmarks.push_back({number(p.at(0), json_path), number(p.at(1), json_path)});
    const nlohmann::json& box = field(f, "box", json_path);
    for (int i = 0; i < 4; ++i) face.box[i] = number(box.at(i), json_path);
    const nlohmann::json& light = field(f, "light_photo_frame", json_path);
    check(light.is_array() && light.size() == 27, "'", json_path, "': light_photo_frame is not 27 numbers; run infer again");
    for (int i = 0; i < 27; ++i) face.photo_light[i] = number(light[i], json_path);
    const std::string face_folder = at(folder, face.folder);
    check(fs::is_directory(face_folder), "'", face_folder, "' is missing: faces.json lists it; run infer again");
    const int s = face.crop_size;
    append_exr_planes(at(face_folder, "normal.exr"), {"X", "Y", "Z"}, s, face.planes);
    std::vector<std::string> vis;
    for (int i = 0; i < 9; ++i) vis.push_back("visibility." + std::to_string(i));
    append_exr_planes(at(face_folder, "visibility.exr"), vis, s, face.planes);
    append_exr_planes(at(face_folder, "albedo.exr"), {"R", "G", "B"}, s, face.planes);
    append_exr_planes(at(face_folder, "shading.exr"), {"R", "G", "B"}, s, face.planes);
    out.faces.push_back(std::move(face));
  }

  // The mask: as faces.json records it, else as asked, or (auto) the shape whose coverage is photo.exr's.
  std::vector<bool> shapes;
  if (json.contains("face_region") && json.contains("feather")) {
    const nlohmann::json& region = json["face_region"];
    check(region.is_string() && (region == "hull" || region == "forehead"), "'", json_path,
          "': face_region is not \"hull\" or \"forehead\"; run infer again");
    out.feather = number(json["feather"], json_path);
    check(out.feather >= 0, "'", json_path, "': feather is negative; run infer again");
    shapes.push_back(region == "forehead");
    out.mask_recorded = true;
  } else {
    if (options.mask != MaskShape::kForehead) shapes.push_back(false);
    if (options.mask != MaskShape::kHull) shapes.push_back(true);
  }
  double best = 1e300;
  bool best_shape = false;
  for (bool forehead : shapes) {
    const double difference = mask_mismatch(out, forehead);
    if (difference < best) {
      best = difference;
      best_shape = forehead;
    }
  }
  out.mask_mismatch = best;
  set_face_geometry(out, best_shape);

  for (const std::string& layer : view_layer_names()) {
    const std::string path = at(folder, layer + ".png");
    const std::string bytes = read_regular_input_file(path, kMaxImageFileBytes, "layer PNG");
    static const std::string kPngSignature = "\x89PNG\r\n\x1a\n";
    check(bytes.compare(0, kPngSignature.size(), kPngSignature) == 0, "'", path, "' is not a PNG; run infer again");
    out.layer_pngs.push_back({layer, std::vector<unsigned char>(bytes.begin(), bytes.end())});
  }
  return out;
}

}  // namespace facetool::view
