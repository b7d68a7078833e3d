// Names of the photo-level layers and of infer's per-photo outputs, their parsing, and the layers each output needs.
#include "libs/photo/photo_outputs.h"

#include <cctype>
#include <iterator>
#include <utility>

#include "core/util/error.h"

namespace facetool {
namespace {

constexpr PhotoLayer kLayers[] = {PhotoLayer::kAlbedo, PhotoLayer::kNormal, PhotoLayer::kVisibility,
                                  PhotoLayer::kShading, PhotoLayer::kReconstruction};

struct OutputName {
  PhotoOutput output;
  const char* name;
};
constexpr OutputName kOutputs[] = {
    {PhotoOutput::kAlbedo, "albedo"},         {PhotoOutput::kNormal, "normal"},
    {PhotoOutput::kVisibility, "visibility"}, {PhotoOutput::kShading, "shading"},
    {PhotoOutput::kReconstruction, "reconstruction"}, {PhotoOutput::kExr, "exr"},
    {PhotoOutput::kFaces, "faces"},           {PhotoOutput::kContactSheet, "contact-sheet"},
    {PhotoOutput::kFaceFolders, "face-folders"},
};

std::string trimmed(const std::string& text) {
  size_t begin = 0, end = text.size();
  while (begin < end && std::isspace(static_cast<unsigned char>(text[begin]))) ++begin;
  while (end > begin && std::isspace(static_cast<unsigned char>(text[end - 1]))) --end;
  return text.substr(begin, end - begin);
}

}  // namespace

const char* photo_layer_name(PhotoLayer layer) {
  switch (layer) {
    case PhotoLayer::kAlbedo: return "albedo";
    case PhotoLayer::kNormal: return "normal";
    case PhotoLayer::kVisibility: return "visibility";
    case PhotoLayer::kShading: return "shading";
    case PhotoLayer::kReconstruction: return "reconstruction";
  }
  return "?";
}

const std::vector<PhotoLayer>& all_photo_layers() {
  static const std::vector<PhotoLayer> layers(std::begin(kLayers), std::end(kLayers));
  return layers;
}

PhotoLayerSet parse_photo_layers(const std::vector<std::string>& names, const std::string& what) {
  std::string valid;
  for (PhotoLayer layer : kLayers) valid += std::string(valid.empty() ? "" : ", ") + photo_layer_name(layer);
  check(!names.empty(), what, ": an empty list; name one or more of ", valid);
  PhotoLayerSet set = PhotoLayerSet::none();
  for (const std::string& name : names) {
    bool known = false;
    for (PhotoLayer layer : kLayers)
      if (name == photo_layer_name(layer)) {
        check(!set.has(layer), what, ": '", name, "' is named twice");
        set.add(layer);
        known = true;
      }
    check(known, what, ": unknown layer '", name, "'; the layers are ", valid);
  }
  return set;
}

PhotoLayerSet PhotoOutputs::layers() const {
  if (has(PhotoOutput::kExr)) return PhotoLayerSet::all();
  PhotoLayerSet set = PhotoLayerSet::none();
  const std::pair<PhotoOutput, PhotoLayer> pngs[] = {
      {PhotoOutput::kAlbedo, PhotoLayer::kAlbedo},   {PhotoOutput::kNormal, PhotoLayer::kNormal},
      {PhotoOutput::kVisibility, PhotoLayer::kVisibility}, {PhotoOutput::kShading, PhotoLayer::kShading},
      {PhotoOutput::kReconstruction, PhotoLayer::kReconstruction}};
  for (const auto& [output, layer] : pngs)
    if (has(output)) set.add(layer);
  return set;
}

std::string PhotoOutputs::names() const {
  std::string list;
  for (const OutputName& o : kOutputs)
    if (has(o.output)) list += std::string(list.empty() ? "" : ",") + o.name;
  return list;
}

std::string PhotoOutputs::valid_names() {
  std::string list;
  for (const OutputName& o : kOutputs) list += std::string(list.empty() ? "" : ", ") + o.name;
  return list + ", all";
}

PhotoOutputs PhotoOutputs::parse(const std::string& list, const std::string& what) {
  unsigned bits = 0;
  size_t start = 0;
  while (true) {
    const size_t comma = list.find(',', start);
    const std::string name = trimmed(list.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    check(!name.empty(), what, ": an empty name in '", list, "'; give names separated by commas, of ", valid_names());
    bool known = name == "all";
    if (known) bits = kAllBits;
    for (const OutputName& o : kOutputs)
      if (name == o.name) {
        bits |= bit(o.output);
        known = true;
      }
    check(known, what, ": unknown output '", name, "'; the outputs are ", valid_names());
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return PhotoOutputs(bits);
}

}  // namespace facetool
