// The self-contained HTML page of `facetool view` (one per decomposed photo) and the run's index.
#pragma once

#include <string>
#include <vector>

#include "core/sh/sh_types.h"
#include "libs/view/view_inputs.h"

namespace facetool::view {

// A light the page offers in its presets menu (photo frame).
struct LightPreset {
  std::string name;
  sh::RgbLight light{};
};

// The whole page: the layers as PNG data URLs, each face's crop layers (16-bit, packed), its
// mask, light and turn into the crop frame, the renderer's triple-product table, and the page's
// script and style inline. Every name is HTML-escaped (and JSON-escaped in the data).
std::string view_page_html(const ViewPhoto& photo, const std::vector<LightPreset>& presets);

// One entry of the run's index: the page's folder (relative to the index) and its thumbnail.
struct IndexEntry {
  std::string name;
  std::string page;  // relative URL of the page, e.g. "photo/view.html"
  std::vector<unsigned char> thumbnail_png;
};
std::string index_page_html(const std::vector<IndexEntry>& entries);

// A small PNG of the photo (its longer side `size` pixels) for the index.
std::vector<unsigned char> thumbnail_png(const ViewPhoto& photo, int size);

// Escapes &, <, >, " and ' for HTML text and attribute values.
std::string html_escape(const std::string& text);

}  // namespace facetool::view
