// safetensors files: a JSON header plus raw little-endian tensor data (read, validate, write).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace facetool {

// The format (https://github.com/huggingface/safetensors): 8 bytes little-endian header length
// N, N bytes of JSON {"__metadata__": {string: string}, "<name>": {"dtype": "F32", "shape":
// [...], "data_offsets": [begin, end]}, ...}, then the data; offsets count from the data start.
class SafeTensors {
 public:
  struct Entry {
    std::string name;
    std::string dtype;           // "F32", "F16", "I64", ...
    std::vector<int64_t> shape;  // any rank, possibly empty (a scalar)
    uint64_t begin = 0;          // byte offsets into the data section
    uint64_t end = 0;
  };

  // Reads and validates a whole file; `what` names it in errors (usually the path). Throws
  // facetool::Error for a missing, truncated or malformed file: bad header length, invalid JSON,
  // unknown dtype, negative or overflowing shape, offsets outside the data or disagreeing with
  // the shape, overlapping tensors.
  static SafeTensors read_file(const std::string& path);
  static SafeTensors parse(const uint8_t* bytes, size_t size, const std::string& what);

  const std::map<std::string, std::string>& metadata() const { return metadata_; }
  std::vector<std::string> names() const;  // sorted
  bool contains(const std::string& name) const { return entries_.count(name) != 0; }
  const Entry& entry(const std::string& name) const;
  // The values of an F32 tensor; fails naming the tensor if it is missing or of another dtype.
  std::vector<float> floats(const std::string& name) const;

 private:
  // Checks the header at `bytes` (the 8-byte length and the JSON; the data need not follow)
  // against a file of `size` bytes: every check of parse, data not read.
  static SafeTensors parse_header(const uint8_t* bytes, uint64_t size, const std::string& what);

  std::string what_;
  std::map<std::string, std::string> metadata_;
  std::map<std::string, Entry> entries_;
  std::vector<uint8_t> data_;
};

// Collects float32 tensors and metadata, then writes them as one safetensors file, atomically
// (to a temporary name in the same folder, then renamed).
class SafeTensorsWriter {
 public:
  void set_metadata(const std::string& key, const std::string& value) { metadata_[key] = value; }
  void add(const std::string& name, const std::vector<int64_t>& shape, std::vector<float> values);
  void write_file(const std::string& path) const;
  std::vector<uint8_t> serialize() const;

 private:
  struct Pending {
    std::vector<int64_t> shape;
    std::vector<float> values;
  };
  std::map<std::string, std::string> metadata_;
  std::map<std::string, Pending> tensors_;
};

}  // namespace facetool
