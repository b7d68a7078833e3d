// Encoding the fit's products: EXR layers, PNG mask, textured OBJ, JSON.
#include "libs/fit/fit_outputs.h"

#include <filesystem>
#include <iomanip>
#include <sstream>

#include "libs/io/exr_io.h"
#include "libs/io/layered_image.h"

namespace fs = std::filesystem;

namespace facetool {

namespace {

std::string json_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
      out += buffer;
      continue;
    }
    out += c;
  }
  return out;
}

FileContents exr(const std::string& path, const std::vector<float>& planar, int w, int h,
                 const std::vector<std::string>& names, const std::string& source) {
  LayeredImage image(w, h, names);
  std::copy(planar.begin(), planar.end(), image.pixels.begin());
  image.set_metadata("facetool:source", source);
  return {path, encode_exr(path, image)};
}

}  // namespace

std::string fit_json(const FitBasis& basis, const FaceFit& fit, const DetectedFace& face,
                     const std::string& source) {
  std::ostringstream o;
  o << std::setprecision(9);
  const HeadPose pose = fit.pose();
  o << "{\n  \"source\": \"" << json_escape(source) << "\",\n  \"image_size\": [" << fit.width << ", "
    << fit.height << "],\n  \"detection\": {\"box\": [" << face.left << ", " << face.top << ", " << face.right
    << ", " << face.bottom << "], \"score\": " << face.score << "},\n  \"camera\": {\"model\": \""
    << fit_camera_name(fit.camera) << "\", \"principal_point\": [" << fit.cx << ", " << fit.cy << "]";
  if (fit.camera == FitCamera::kPerspective)
    o << ", \"focal_px\": " << fit.focal_px << ", \"units\": \"model (ICT, centimetres)\"";
  else
    o << ", \"scale_px_per_model_unit\": " << fit.scale << ", \"units\": \"pixels\"";
  o << ", \"frame\": \"+X right, +Y up, +Z to the viewer\"},\n  \"pose\": {\"angle_axis\": [" << fit.rotation[0]
    << ", " << fit.rotation[1] << ", " << fit.rotation[2] << "], \"roll_deg\": " << pose.roll_deg
    << ", \"pitch_deg\": " << pose.pitch_deg << ", \"yaw_deg\": " << pose.yaw_deg << ", \"translation\": ["
    << fit.translation[0] << ", " << fit.translation[1] << ", " << fit.translation[2] << "]},\n  \"identity\": [";
  for (size_t k = 0; k < fit.identity.size(); ++k) o << (k ? ", " : "") << fit.identity[k];
  o << "],\n  \"expression\": {";
  for (size_t e = 0; e < fit.expression.size(); ++e)
    o << (e ? ", " : "") << "\"" << json_escape(basis.model().expression_names()[e]) << "\": " << fit.expression[e];
  o << "},\n  \"landmarks\": [";
  for (int i = 0; i < kLandmarkCount; ++i)
    o << (i ? ", " : "") << "[" << face.landmarks[i].x << ", " << face.landmarks[i].y << "]";
  o << "],\n  \"landmark_vertices\": [";
  for (int i = 0; i < kLandmarkCount; ++i) o << (i ? ", " : "") << fit.vertices[i];
  o << "],\n  \"landmark_rms_px\": " << fit.rms_px << ",\n  \"iterations\": " << fit.iterations
    << ",\n  \"fit_seconds\": " << fit.seconds << "\n}\n";
  return o.str();
}

std::string fitted_mesh_obj(const FaceFit& fit, const FaceMesh& mesh, const std::string& mtl_name) {
  std::ostringstream o;
  o << std::setprecision(7) << "# facetool fit: the fitted ICT face model in the camera frame (+X right, +Y up, "
    << "+Z to the viewer); texture coordinates project each vertex into the photo\nmtllib " << mtl_name
    << "\nusemtl photo\n";
  for (const Vec3f& p : mesh.positions) o << "v " << p.x << ' ' << p.y << ' ' << p.z << '\n';
  for (const Vec3f& p : mesh.positions) {
    const Point2 px = fit.project(p);
    o << "vt " << (px.x + 0.5) / fit.width << ' ' << 1.0 - (px.y + 0.5) / fit.height << '\n';
  }
  for (const auto& t : mesh.triangles)
    o << "f " << t[0] + 1 << '/' << t[0] + 1 << ' ' << t[1] + 1 << '/' << t[1] + 1 << ' ' << t[2] + 1 << '/'
      << t[2] + 1 << '\n';
  return o.str();
}

std::vector<FileContents> fit_product_files(const std::string& folder, const FitBasis& basis,
                                            const FaceFit& fit, const FitRendering& r,
                                            const DetectedFace& face, const RgbImage& texture,
                                            const std::string& source) {
  auto at = [&](const char* name) { return (fs::path(folder) / name).string(); };
  const int w = r.width, h = r.height;
  const size_t plane = static_cast<size_t>(w) * h;
  std::vector<FileContents> files;
  files.push_back(exr(at("normal.exr"), r.normal, w, h, {"X", "Y", "Z"}, source));
  files.push_back(exr(at("depth.exr"), r.depth, w, h, {"Z"}, source));
  std::vector<std::string> vis;
  for (int i = 0; i < 9; ++i) vis.push_back("visibility." + std::to_string(i));
  files.push_back(exr(at("visibility.exr"), r.visibility, w, h, vis, source));
  RgbImage mask;
  mask.width = w;
  mask.height = h;
  mask.pixels.resize(plane * 3);
  for (size_t p = 0; p < plane; ++p)
    for (int c = 0; c < 3; ++c) mask.pixels[p * 3 + c] = r.mask[p] ? 1.0f : 0.0f;
  files.push_back({at("mask.png"), encode_png(at("mask.png"), mask, false)});
  files.push_back({at("texture.png"), encode_png(at("texture.png"), texture, true)});
  const std::string mtl = "# facetool fit: the photo as the fitted mesh's texture\nnewmtl photo\nKd 1 1 1\nmap_Kd texture.png\n";
  files.push_back({at("mesh.mtl"), std::vector<unsigned char>(mtl.begin(), mtl.end())});
  const std::string obj = fitted_mesh_obj(fit, r.mesh, "mesh.mtl");
  files.push_back({at("mesh.obj"), std::vector<unsigned char>(obj.begin(), obj.end())});
  const std::string json = fit_json(basis, fit, face, source);
  files.push_back({at("fit.json"), std::vector<unsigned char>(json.begin(), json.end())});
  return files;
}

}  // namespace facetool
