// OBJ parsing: a single pass over the text with strtof/strtol, tolerant of comments and unknown
// statements (vn, s, o, mtllib, ...), strict about numbers and indices.
#include "libs/io/obj_reader.h"

#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "core/util/error.h"
#include "core/util/file_checks.h"

namespace facetool {
namespace {

class LineParser {
 public:
  LineParser(const char* begin, const char* end, const std::string& source, int64_t line)
      : cursor_(begin), end_(end), source_(source), line_(line) {}

  void skip_spaces() {
    while (cursor_ < end_ && (*cursor_ == ' ' || *cursor_ == '\t' || *cursor_ == '\r')) ++cursor_;
  }
  bool at_end() {
    skip_spaces();
    return cursor_ >= end_;
  }
  // The next whitespace-separated token.
  std::string word() {
    skip_spaces();
    const char* start = cursor_;
    while (cursor_ < end_ && *cursor_ != ' ' && *cursor_ != '\t' && *cursor_ != '\r') ++cursor_;
    return std::string(start, cursor_);
  }
  float number() {
    skip_spaces();
    const char* start = cursor_;
    if (cursor_ < end_ && *cursor_ == '+') ++cursor_;  // from_chars takes no leading '+'
    float value = 0.0f;
    const auto [after, status] = std::from_chars(cursor_, end_, value);
    const bool separated = after == end_ || *after == ' ' || *after == '\t' || *after == '\r';
    if (status != std::errc() || !separated) {
      const char* stop = start;
      while (stop < end_ && *stop != ' ' && *stop != '\t' && *stop != '\r') ++stop;
      error("expected a number, found '", std::string(start, stop), "'");
    }
    cursor_ = after;
    return value;
  }
  template <typename... Parts>
  [[noreturn]] void error(const Parts&... parts) const {
    fail("OBJ file '", source_, "' line ", line_, ": ", parts...,
         "; fix or re-export the file");
  }

 private:
  const char* cursor_;
  const char* end_;
  const std::string& source_;
  int64_t line_;
};

// Resolves a 1-based (or negative, relative) OBJ index against `count` items.
int32_t resolve_index(long raw, size_t count, const LineParser& parser, const char* what) {
  long index = raw > 0 ? raw - 1 : static_cast<long>(count) + raw;
  if (raw == 0 || index < 0 || index >= static_cast<long>(count))
    parser.error(what, " index ", raw, " is outside the ", count, " defined so far");
  return static_cast<int32_t>(index);
}

int32_t name_index(const std::string& name, std::vector<std::string>& names,
                   std::unordered_map<std::string, int32_t>& lookup) {
  auto found = lookup.find(name);
  if (found != lookup.end()) return found->second;
  const auto index = static_cast<int32_t>(names.size());
  names.push_back(name);
  lookup.emplace(name, index);
  return index;
}

}  // namespace

ObjMesh parse_obj(const std::string& text, const std::string& source_name) {
  ObjMesh mesh;
  std::unordered_map<std::string, int32_t> material_lookup, group_lookup;
  int32_t material = -1, group = -1;
  std::vector<int32_t> corner_positions, corner_texcoords;
  const char* cursor = text.data();
  const char* const text_end = text.data() + text.size();
  int64_t line_number = 0;
  while (cursor < text_end) {
    const char* line_end = cursor;
    while (line_end < text_end && *line_end != '\n') ++line_end;
    ++line_number;
    LineParser line(cursor, line_end, source_name, line_number);
    cursor = line_end < text_end ? line_end + 1 : text_end;
    if (line.at_end()) continue;
    const std::string keyword = line.word();
    if (keyword[0] == '#') continue;
    if (keyword == "v") {
      std::array<float, 3> p{line.number(), line.number(), line.number()};
      mesh.positions.push_back(p);  // an optional w or vertex colour is ignored
    } else if (keyword == "vt") {
      std::array<float, 2> t{line.number(), 0.0f};
      if (!line.at_end()) t[1] = line.number();
      mesh.texcoords.push_back(t);
    } else if (keyword == "f") {
      corner_positions.clear();
      corner_texcoords.clear();
      while (!line.at_end()) {
        const std::string corner = line.word();
        const char* c = corner.c_str();
        char* after = nullptr;
        errno = 0;
        const long position = std::strtol(c, &after, 10);
        if (after == c || errno != 0) line.error("malformed face corner '", corner, "'");
        corner_positions.push_back(resolve_index(position, mesh.positions.size(), line, "vertex"));
        int32_t texcoord = -1;
        if (*after == '/' && after[1] != '/' && after[1] != '\0') {
          const char* t = after + 1;
          const long raw = std::strtol(t, &after, 10);
          if (after == t) line.error("malformed face corner '", corner, "'");
          texcoord = resolve_index(raw, mesh.texcoords.size(), line, "texture coordinate");
        }
        corner_texcoords.push_back(texcoord);
      }
      if (corner_positions.size() < 3)
        line.error("a face needs at least 3 corners, found ", corner_positions.size());
      for (size_t k = 1; k + 1 < corner_positions.size(); ++k) {
        mesh.triangles.push_back({corner_positions[0], corner_positions[k], corner_positions[k + 1]});
        mesh.triangle_texcoords.push_back(
            {corner_texcoords[0], corner_texcoords[k], corner_texcoords[k + 1]});
        mesh.triangle_polygon.push_back(mesh.polygon_count);
        mesh.triangle_material.push_back(material);
        mesh.triangle_group.push_back(group);
      }
      ++mesh.polygon_count;
    } else if (keyword == "usemtl") {
      material = name_index(line.word(), mesh.materials, material_lookup);
    } else if (keyword == "g") {
      group = name_index(line.word(), mesh.groups, group_lookup);
    }
  }
  return mesh;
}

ObjMesh read_obj(const std::string& path) {
  return parse_obj(read_regular_input_file(path, kMaxMeshFileBytes, "OBJ file"), path);
}

}  // namespace facetool
