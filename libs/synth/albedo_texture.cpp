// Albedo textures: the frontal texture frame, bilinear look-up and the EXR files.
#include "libs/synth/albedo_texture.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/util/error.h"
#include "core/util/memory_budget.h"
#include "libs/io/exr_io.h"
#include "libs/io/layered_image.h"

namespace facetool {

AlbedoTextureFrame albedo_texture_frame(const FaceMesh& reference, int size) {
  check(size >= 8 && size <= 4096, "albedo texture size must be in [8, 4096], got ", size);
  check(!reference.fit_vertices.empty(), "albedo texture frame: the mesh has no face-region vertices");
  float x0 = 1e30f, x1 = -1e30f, y0 = 1e30f, y1 = -1e30f;
  for (const int32_t v : reference.fit_vertices) {
    const Vec3f p = reference.reference_positions[static_cast<size_t>(v)];
    x0 = std::min(x0, p.x);
    x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y);
    y1 = std::max(y1, p.y);
  }
  AlbedoTextureFrame frame;
  frame.size = size;
  frame.span = 1.1f * std::max(x1 - x0, y1 - y0);
  frame.left = 0.5f * (x0 + x1) - 0.5f * frame.span;
  frame.top = 0.5f * (y0 + y1) + 0.5f * frame.span;
  return frame;
}

void albedo_texel(const AlbedoTextureFrame& frame, Vec3f reference, bool mirror, float& u, float& v) {
  float x = reference.x;
  if (mirror) x = 2.0f * frame.left + frame.span - x;
  u = (x - frame.left) / frame.span * static_cast<float>(frame.size) - 0.5f;
  v = (frame.top - reference.y) / frame.span * static_cast<float>(frame.size) - 0.5f;
}

void sample_albedo_texture(const AlbedoTexture& texture, Vec3f reference, bool mirror, Vec3f& rgb, float& weight) {
  const int n = texture.frame.size;
  float u, v;
  albedo_texel(texture.frame, reference, mirror, u, v);
  u = std::clamp(u, 0.0f, static_cast<float>(n - 1));
  v = std::clamp(v, 0.0f, static_cast<float>(n - 1));
  const int x0 = static_cast<int>(u), y0 = static_cast<int>(v);  // u, v >= 0: truncation is floor
  const int x1 = std::min(x0 + 1, n - 1), y1 = std::min(y0 + 1, n - 1);
  const float fx = u - static_cast<float>(x0), fy = v - static_cast<float>(y0);
  const size_t plane = static_cast<size_t>(n) * n;
  auto at = [&](const float* data, int x, int y) { return data[static_cast<size_t>(y) * n + x]; };
  auto bilinear = [&](const float* data) {
    return (1 - fy) * ((1 - fx) * at(data, x0, y0) + fx * at(data, x1, y0)) +
           fy * ((1 - fx) * at(data, x0, y1) + fx * at(data, x1, y1));
  };
  for (int c = 0; c < 3; ++c) rgb[c] = bilinear(texture.rgb.data() + c * plane);
  weight = bilinear(texture.weight.data());
}

Vec3f mean_albedo(const AlbedoTexture& texture) {
  const size_t plane = texture.weight.size();
  double sum[3] = {0, 0, 0}, total = 0;
  for (size_t p = 0; p < plane; ++p) {
    total += texture.weight[p];
    for (int c = 0; c < 3; ++c) sum[c] += static_cast<double>(texture.weight[p]) * texture.rgb[c * plane + p];
  }
  if (total <= 0) return {0, 0, 0};
  return {static_cast<float>(sum[0] / total), static_cast<float>(sum[1] / total), static_cast<float>(sum[2] / total)};
}

namespace {
constexpr const char* kFrameKey = "facetool:albedo_texture_frame";
}  // namespace

void write_albedo_texture(const std::string& path, const AlbedoTexture& texture) {
  const int n = texture.frame.size;
  const size_t plane = static_cast<size_t>(n) * n;
  check(texture.rgb.size() == 3 * plane && texture.weight.size() == plane, "albedo texture '", path,
        "': its planes do not match its ", n, "x", n, " frame");
  LayeredImage image(n, n, {"R", "G", "B", "A"});
  for (int c = 0; c < 3; ++c) std::copy(texture.rgb.begin() + c * plane, texture.rgb.begin() + (c + 1) * plane, image.plane(c));
  std::copy(texture.weight.begin(), texture.weight.end(), image.plane(3));
  char frame[160];
  std::snprintf(frame, sizeof frame, "%d %.9g %.9g %.9g", n, texture.frame.left, texture.frame.top, texture.frame.span);
  image.set_metadata(kFrameKey, frame);
  image.set_metadata("facetool:source", texture.source);
  write_exr_atomically(path, image);
}

AlbedoTexture read_albedo_texture(const std::string& path) {
  const LayeredImage image = read_exr(path);
  const std::string* frame_text = image.find_metadata(kFrameKey);
  check(frame_text != nullptr, "albedo texture '", path, "' has no ", kFrameKey,
        " attribute; make textures with `facetool unwrap`");
  AlbedoTexture texture;
  std::istringstream in(*frame_text);
  in >> texture.frame.size >> texture.frame.left >> texture.frame.top >> texture.frame.span;
  check(!in.fail() && texture.frame.size == image.width && image.width == image.height && texture.frame.span > 0 &&
            std::isfinite(texture.frame.left) && std::isfinite(texture.frame.top) && std::isfinite(texture.frame.span),
        "albedo texture '", path, "': ", kFrameKey, " '", *frame_text, "' does not describe its ", image.width, "x",
        image.height, " image (expected \"size left top span\" of a square image)");
  const size_t plane = image.plane_size();
  texture.rgb.resize(3 * plane);
  texture.weight.resize(plane);
  const char* names[4] = {"R", "G", "B", "A"};
  for (int c = 0; c < 4; ++c) {
    const int k = image.find_channel(names[c]);
    check(k >= 0, "albedo texture '", path, "' has no channel ", names[c]);
    const float* data = image.plane(k);
    for (size_t p = 0; p < plane; ++p)
      check(std::isfinite(data[p]), "albedo texture '", path, "': channel ", names[c], " holds a non-finite value");
    std::copy(data, data + plane, c < 3 ? texture.rgb.begin() + c * plane : texture.weight.begin());
  }
  if (const std::string* source = image.find_metadata("facetool:source")) texture.source = *source;
  return texture;
}

std::vector<AlbedoTexture> read_albedo_textures(const std::string& folder) {
  namespace fs = std::filesystem;
  check(fs::is_directory(folder), "albedo textures: '", folder, "' is not a folder; make one with `facetool unwrap`");
  std::vector<std::string> files;
  for (const fs::directory_entry& e : fs::directory_iterator(folder))
    if (e.is_regular_file() && e.path().extension() == ".exr") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  check(!files.empty(), "albedo textures: '", folder, "' holds no .exr file; make them with `facetool unwrap`");
  // All are held at once: 16 bytes per texel, the first file's size for all.
  const uint64_t texels = static_cast<uint64_t>(read_exr_header(files.front()).plane_size());
  check_memory_budget(16 * texels * files.size(), "reading the " + std::to_string(files.size()) +
                                                      " albedo textures of '" + folder + "' (use fewer)");
  std::vector<AlbedoTexture> textures;
  textures.reserve(files.size());
  for (const std::string& file : files) {
    textures.push_back(read_albedo_texture(file));
    check(textures.back().frame == textures.front().frame, "albedo texture '", file, "' has another frame than '",
          files.front(), "' (made for another face model or size); keep one kind per folder");
  }
  return textures;
}

}  // namespace facetool
