// Assembling the view page: the data block (layers, faces, lights, the triple-product table) and
// the embedded template (libs/view/page/).
#include "libs/view/view_page.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>

#include "core/sh/triple_product.h"
#include "core/util/error.h"
#include "libs/face/landmark_drawing.h"
#include "libs/io/image_io.h"
#include "libs/view/base64.h"

namespace facetool::view {
namespace page_files {
const char* kernel_source(const std::string& file_name);  // generated: libs/view/page/* embedded
}  // namespace page_files

namespace {

std::string page_file(const std::string& name) {
  const char* text = page_files::kernel_source(name);
  check(text != nullptr, "view page: the template file '", name, "' is not embedded (a build error)");
  return text;
}

std::string data_url(const std::vector<unsigned char>& png) {
  return "data:image/png;base64," + base64_encode(png.data(), png.size());
}

RgbImage image_of(int width, int height, const std::vector<float>& interleaved) {
  RgbImage image;
  image.width = width;
  image.height = height;
  image.pixels = interleaved;
  return image;
}

// Planes quantised to 16 bits each, between their own minimum and maximum: the page reads
// v = min + q (max - min) / 65535. Returns the little-endian bytes; `ranges` gets min, max per plane.
std::vector<unsigned char> pack_planes(const std::vector<float>& planes, size_t plane, std::vector<double>& ranges) {
  std::vector<unsigned char> bytes(planes.size() * 2);
  for (size_t c = 0; c * plane < planes.size(); ++c) {
    const float* p = planes.data() + c * plane;
    const float lo = *std::min_element(p, p + plane), hi = *std::max_element(p, p + plane);
    ranges.push_back(lo);
    ranges.push_back(hi);
    const double scale = hi > lo ? 65535.0 / (static_cast<double>(hi) - lo) : 0.0;
    for (size_t i = 0; i < plane; ++i) {
      const auto q = static_cast<uint16_t>(std::lround(std::clamp((p[i] - static_cast<double>(lo)) * scale, 0.0, 65535.0)));
      bytes[(c * plane + i) * 2] = static_cast<unsigned char>(q & 0xff);
      bytes[(c * plane + i) * 2 + 1] = static_cast<unsigned char>(q >> 8);
    }
  }
  return bytes;
}

nlohmann::json light_json(const sh::RgbLight& light) {
  nlohmann::json out = nlohmann::json::array();
  for (double v : light) out.push_back(v);
  return out;
}

nlohmann::json page_data(const ViewPhoto& photo, const std::vector<LightPreset>& presets) {
  nlohmann::json data;
  data["name"] = photo.name;
  data["source"] = photo.source;
  data["width"] = photo.width;
  data["height"] = photo.height;
  data["feather"] = photo.feather;
  data["mask_shape"] = photo.mask_shape;
  data["mask_mismatch"] = photo.mask_mismatch;
  data["photo"] = data_url(encode_png("photo", image_of(photo.width, photo.height, photo.photo)));
  std::vector<float> mask(photo.alpha.size() * 3);
  for (size_t i = 0; i < photo.alpha.size(); ++i) std::fill_n(mask.begin() + i * 3, 3, photo.alpha[i]);
  data["mask"] = data_url(encode_png("mask", image_of(photo.width, photo.height, mask), false));
  nlohmann::json layers = nlohmann::json::array();
  for (const auto& [name, png] : photo.layer_pngs) layers.push_back({{"name", name}, {"url", data_url(png)}});
  data["layers"] = layers;
  nlohmann::json triple = nlohmann::json::array();
  for (const sh::TripleEntry& e : sh::TripleProductTable::get().all_entries())
    triple.push_back({e.i, e.j, e.k, static_cast<float>(e.value)});
  data["triple"] = triple;
  nlohmann::json faces = nlohmann::json::array();
  for (const ViewFace& face : photo.faces) {
    nlohmann::json f;
    f["folder"] = face.folder;
    f["crop_size"] = face.crop_size;
    f["photo_to_crop"] = {face.photo_to_crop.a, face.photo_to_crop.b, face.photo_to_crop.tx, face.photo_to_crop.ty};
    nlohmann::json landmarks = nlohmann::json::array();
    for (const Point2& p : face.landmarks) landmarks.push_back({p.x, p.y});
    f["landmarks"] = landmarks;
    f["box"] = face.box;
    f["region"] = face.region;
    nlohmann::json lines = nlohmann::json::array();
    for (const auto& line : face.mask_lines) lines.push_back(line);
    f["mask_lines"] = lines;
    f["light"] = light_json(face.photo_light);
    f["to_crop"] = face.photo_to_crop_sh;
    std::vector<double> ranges;
    const std::vector<unsigned char> packed =
        pack_planes(face.planes, static_cast<size_t>(face.crop_size) * face.crop_size, ranges);
    f["ranges"] = ranges;
    f["planes"] = base64_encode(packed.data(), packed.size());
    faces.push_back(f);
  }
  data["faces"] = faces;
  nlohmann::json lights = nlohmann::json::array();
  for (const LightPreset& p : presets) lights.push_back({{"name", p.name}, {"light", light_json(p.light)}});
  data["presets"] = lights;
  return data;
}

// JSON safe inside <script>: '<', '>' and '&' (only ever inside strings) as \u escapes.
std::string script_safe_json(const nlohmann::json& value) {
  const std::string text = value.dump(-1, ' ', true, nlohmann::json::error_handler_t::replace);
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    if (c == '<') out += "\\u003c";
    else if (c == '>') out += "\\u003e";
    else if (c == '&') out += "\\u0026";
    else out += c;
  }
  return out;
}

// `text` with each "{{KEY}}" of `values` replaced once, in one pass (a value is never rescanned).
std::string fill(const std::string& text, const std::vector<std::pair<std::string, std::string>>& values) {
  std::string out;
  size_t from = 0;
  while (true) {
    const size_t open = text.find("{{", from);
    if (open == std::string::npos) break;
    const size_t close = text.find("}}", open);
    check(close != std::string::npos, "view page: an unclosed {{ in the template (a build error)");
    const std::string key = text.substr(open + 2, close - open - 2);
    const auto it = std::find_if(values.begin(), values.end(), [&](const auto& v) { return v.first == key; });
    check(it != values.end(), "view page: the template's {{", key, "}} has no value (a build error)");
    out.append(text, from, open - from);
    out += it->second;
    from = close + 2;
  }
  out.append(text, from, std::string::npos);
  return out;
}

}  // namespace

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string view_page_html(const ViewPhoto& photo, const std::vector<LightPreset>& presets) {
  return fill(page_file("view.html"), {{"TITLE", html_escape(photo.name)},
                                       {"STYLE", page_file("view.css")},
                                       {"DATA", script_safe_json(page_data(photo, presets))},
                                       {"SCRIPT", page_file("view.js")}});
}

std::string index_page_html(const std::vector<IndexEntry>& entries) {
  std::string items;
  for (const IndexEntry& e : entries)
    items += "<a class=\"entry\" href=\"" + html_escape(e.page) + "\"><img alt=\"\" src=\"" + data_url(e.thumbnail_png) +
             "\"><span>" + html_escape(e.name) + "</span></a>\n";
  return fill(page_file("index.html"), {{"STYLE", page_file("view.css")}, {"ENTRIES", items}});
}

std::vector<unsigned char> thumbnail_png(const ViewPhoto& photo, int size) {
  const RgbImage image = image_of(photo.width, photo.height, photo.photo);
  const int width = photo.width >= photo.height ? size : std::max(1, photo.width * size / photo.height);
  return encode_png("thumbnail", resize_to_width(image, width));
}

}  // namespace facetool::view
