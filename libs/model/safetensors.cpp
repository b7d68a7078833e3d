// safetensors: parsing with full validation, and atomic writing.
#include "libs/model/safetensors.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <new>
#include <set>

#include <nlohmann/json.hpp>

#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "core/util/memory_budget.h"

namespace facetool {
namespace {

constexpr uint64_t kMaxHeaderBytes = 100u << 20;  // the reference implementation's limit

size_t dtype_size(const std::string& dtype) {
  static const std::map<std::string, size_t> sizes = {
      {"F64", 8}, {"F32", 4}, {"F16", 2}, {"BF16", 2}, {"I64", 8}, {"I32", 4}, {"I16", 2},
      {"I8", 1},  {"U64", 8}, {"U32", 4}, {"U16", 2},  {"U8", 1},  {"BOOL", 1}};
  auto it = sizes.find(dtype);
  return it == sizes.end() ? 0 : it->second;
}

uint64_t read_u64_le(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

}  // namespace

SafeTensors SafeTensors::read_file(const std::string& path) {
  // The header is read and checked first: a file whose header does not account for its size
  // (a sparse or padded file, a truncated one) is refused before its data is read, and the data
  // is read once, straight into place.
  const uint64_t size = check_regular_input_file(path, kMaxWeightsFileBytes, "weights file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("weights file '", path, "' cannot be read: ", std::strerror(errno));
  std::vector<uint8_t> prefix(std::min<uint64_t>(size, 8));
  in.read(reinterpret_cast<char*>(prefix.data()), static_cast<std::streamsize>(prefix.size()));
  if (prefix.size() == 8) {
    const uint64_t header_len = read_u64_le(prefix.data());
    if (header_len <= kMaxHeaderBytes && header_len <= size - 8) {
      prefix.resize(8 + header_len);
      in.read(reinterpret_cast<char*>(prefix.data()) + 8, static_cast<std::streamsize>(header_len));
    }
  }
  if (!in)
    fail("cannot read weights file '", path, "': it changed or could not be read completely");
  SafeTensors st = parse_header(prefix.data(), size, path);
  const uint64_t data_size = size - prefix.size();
  const std::string what = "reading weights file '" + path + "'";
  check_memory_budget(data_size, what);
  try {
    st.data_.resize(data_size);
  } catch (const std::bad_alloc&) {
    throw out_of_memory(what, data_size);
  }
  in.read(reinterpret_cast<char*>(st.data_.data()), static_cast<std::streamsize>(data_size));
  if (static_cast<uint64_t>(in.gcount()) != data_size)
    fail("cannot read weights file '", path, "': it changed or could not be read completely");
  return st;
}

SafeTensors SafeTensors::parse(const uint8_t* bytes, size_t size, const std::string& what) {
  SafeTensors st = parse_header(bytes, size, what);
  const uint64_t header_len = read_u64_le(bytes);
  st.data_.assign(bytes + 8 + header_len, bytes + size);
  return st;
}

SafeTensors SafeTensors::parse_header(const uint8_t* bytes, uint64_t size,
                                      const std::string& what) {
  auto bad = [&](const auto&... parts) { fail("'", what, "' is not a valid safetensors file: ", parts...); };
  if (size < 8) bad("it holds ", size, " bytes, fewer than the 8-byte header length");
  const uint64_t header_len = read_u64_le(bytes);
  if (header_len > kMaxHeaderBytes) bad("header length ", header_len, " exceeds ", kMaxHeaderBytes);
  if (header_len > size - 8)
    bad("header length ", header_len, " runs past the end of the file (", size, " bytes); ",
        "the file is truncated");
  nlohmann::json header;
  // JSON would silently keep the last of two equal keys; safetensors forbids them, so each
  // object's keys are collected while parsing.
  std::vector<std::set<std::string>> keys_of_open_objects;
  std::string duplicate;
  const nlohmann::json::parser_callback_t track_keys =
      [&](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
        if (event == nlohmann::json::parse_event_t::object_start) keys_of_open_objects.emplace_back();
        if (event == nlohmann::json::parse_event_t::object_end && !keys_of_open_objects.empty())
          keys_of_open_objects.pop_back();
        if (event == nlohmann::json::parse_event_t::key && !keys_of_open_objects.empty() &&
            !keys_of_open_objects.back().insert(parsed.get<std::string>()).second &&
            duplicate.empty())
          duplicate = parsed.get<std::string>();
        return true;
      };
  try {
    header = nlohmann::json::parse(bytes + 8, bytes + 8 + header_len, track_keys);
  } catch (const nlohmann::json::exception& e) {
    bad("the JSON header does not parse (", e.what(), ")");
  }
  if (!duplicate.empty()) bad("the JSON header holds the key '", duplicate, "' twice");
  if (!header.is_object()) bad("the JSON header is not an object");

  SafeTensors st;
  st.what_ = what;
  const uint64_t data_size = size - 8 - header_len;
  std::vector<std::pair<uint64_t, uint64_t>> ranges;
  for (auto it = header.begin(); it != header.end(); ++it) {
    const std::string& name = it.key();
    const nlohmann::json& value = it.value();
    if (name == "__metadata__") {
      if (!value.is_object()) bad("__metadata__ is not an object");
      for (auto m = value.begin(); m != value.end(); ++m) {
        if (!m.value().is_string()) bad("metadata value of '", m.key(), "' is not a string");
        st.metadata_[m.key()] = m.value().get<std::string>();
      }
      continue;
    }
    if (!value.is_object()) bad("entry '", name, "' is not an object");
    Entry e;
    e.name = name;
    auto dtype = value.find("dtype");
    auto shape = value.find("shape");
    auto offsets = value.find("data_offsets");
    if (dtype == value.end() || !dtype->is_string()) bad("tensor '", name, "' has no dtype string");
    if (shape == value.end() || !shape->is_array()) bad("tensor '", name, "' has no shape array");
    if (offsets == value.end() || !offsets->is_array() || offsets->size() != 2)
      bad("tensor '", name, "' has no [begin, end] data_offsets");
    e.dtype = dtype->get<std::string>();
    const size_t elem = dtype_size(e.dtype);
    if (elem == 0) bad("tensor '", name, "' has unknown dtype '", e.dtype, "'");
    uint64_t count = 1;
    for (const auto& d : *shape) {
      if (!d.is_number_unsigned()) bad("tensor '", name, "' has a shape entry that is not a ",
                                       "non-negative integer");
      const uint64_t dim = d.get<uint64_t>();
      if (dim != 0 && count > std::numeric_limits<uint64_t>::max() / dim / elem)
        bad("tensor '", name, "' has a shape whose size overflows");
      count *= dim;
      e.shape.push_back(static_cast<int64_t>(std::min<uint64_t>(dim, INT64_MAX)));
    }
    for (const auto& o : *offsets)
      if (!o.is_number_unsigned()) bad("tensor '", name, "' has a non-integer data offset");
    e.begin = (*offsets)[0].get<uint64_t>();
    e.end = (*offsets)[1].get<uint64_t>();
    if (e.begin > e.end || e.end > data_size)
      bad("tensor '", name, "' has data_offsets [", e.begin, ", ", e.end, "] outside the ",
          data_size, " data bytes (truncated file?)");
    if (e.end - e.begin != count * elem)
      bad("tensor '", name, "' holds ", e.end - e.begin, " bytes but its shape and dtype need ",
          count * elem);
    ranges.emplace_back(e.begin, e.end);
    st.entries_.emplace(name, std::move(e));
  }
  std::sort(ranges.begin(), ranges.end());
  for (size_t i = 1; i < ranges.size(); ++i)
    if (ranges[i].first < ranges[i - 1].second) bad("two tensors share data bytes");
  // The format requires the tensors to cover the data bytes exactly: no holes, nothing after.
  uint64_t covered = 0;
  for (const auto& [begin, end] : ranges) {
    if (begin != covered) bad("data bytes ", covered, "..", begin, " belong to no tensor");
    covered = end;
  }
  if (covered != data_size)
    bad(data_size - covered, " trailing bytes after the last tensor's data (", data_size,
        " data bytes, ", covered, " used)");
  return st;
}

std::vector<std::string> SafeTensors::names() const {
  std::vector<std::string> out;
  for (const auto& [name, entry] : entries_) out.push_back(name);
  return out;
}

const SafeTensors::Entry& SafeTensors::entry(const std::string& name) const {
  auto it = entries_.find(name);
  check(it != entries_.end(), "'", what_, "' has no tensor named '", name, "'");
  return it->second;
}

std::vector<float> SafeTensors::floats(const std::string& name) const {
  const Entry& e = entry(name);
  check(e.dtype == "F32", "tensor '", name, "' in '", what_, "' has dtype ", e.dtype,
        " but facetool needs F32");
  std::vector<float> values((e.end - e.begin) / 4);
  const uint8_t* p = data_.data() + e.begin;
  for (size_t i = 0; i < values.size(); ++i, p += 4) {
    const uint32_t bits = uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 |
                          uint32_t(p[3]) << 24;
    std::memcpy(&values[i], &bits, 4);
  }
  return values;
}

void SafeTensorsWriter::add(const std::string& name, const std::vector<int64_t>& shape,
                            std::vector<float> values) {
  check(name != "__metadata__" && !name.empty(), "safetensors: invalid tensor name '", name, "'");
  int64_t count = 1;
  for (int64_t d : shape) count *= d;
  check(count == static_cast<int64_t>(values.size()), "safetensors: tensor '", name, "' has ",
        values.size(), " values but its shape needs ", count);
  check(tensors_.emplace(name, Pending{shape, std::move(values)}).second,
        "safetensors: tensor '", name, "' added twice");
}

std::vector<uint8_t> SafeTensorsWriter::serialize() const {
  nlohmann::json header = nlohmann::json::object();
  if (!metadata_.empty()) header["__metadata__"] = metadata_;
  uint64_t offset = 0;
  for (const auto& [name, t] : tensors_) {
    const uint64_t bytes = t.values.size() * 4;
    header[name] = {{"dtype", "F32"}, {"shape", t.shape}, {"data_offsets", {offset, offset + bytes}}};
    offset += bytes;
  }
  std::string text = header.dump();
  while ((8 + text.size()) % 8 != 0) text.push_back(' ');  // align the data to 8 bytes
  std::vector<uint8_t> out(8 + text.size() + offset);
  const uint64_t n = text.size();
  for (int i = 0; i < 8; ++i) out[i] = static_cast<uint8_t>(n >> (8 * i));
  std::memcpy(out.data() + 8, text.data(), text.size());
  uint8_t* p = out.data() + 8 + text.size();
  for (const auto& [name, t] : tensors_) {
    for (float v : t.values) {
      uint32_t bits;
      std::memcpy(&bits, &v, 4);
      for (int i = 0; i < 4; ++i) *p++ = static_cast<uint8_t>(bits >> (8 * i));
    }
  }
  return out;
}

void SafeTensorsWriter::write_file(const std::string& path) const {
  const std::vector<uint8_t> bytes = serialize();
  write_file_atomically(path, bytes.data(), bytes.size());
}

}  // namespace facetool
