// safetensors: round trip, and every malformed file refused with a clear error, never a crash.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "libs/model/safetensors.h"
#include "core/util/error.h"

namespace facetool {
namespace {

// Builds a file from a header object and raw data, the way a foreign writer might.
std::vector<uint8_t> make_file(const nlohmann::json& header, const std::vector<uint8_t>& data,
                               int64_t header_len_override = -1) {
  const std::string text = header.dump();
  const uint64_t n = header_len_override >= 0 ? uint64_t(header_len_override) : text.size();
  std::vector<uint8_t> out(8 + text.size() + data.size());
  for (int i = 0; i < 8; ++i) out[i] = uint8_t(n >> (8 * i));
  std::copy(text.begin(), text.end(), out.begin() + 8);
  std::copy(data.begin(), data.end(), out.begin() + 8 + text.size());
  return out;
}

std::string parse_error(const std::vector<uint8_t>& bytes) {
  try {
    SafeTensors::parse(bytes.data(), bytes.size(), "test.safetensors");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

nlohmann::json one_tensor(const char* dtype, std::vector<int64_t> shape, uint64_t b, uint64_t e) {
  return {{"w", {{"dtype", dtype}, {"shape", shape}, {"data_offsets", {b, e}}}}};
}

TEST(SafeTensors, RoundTripKeepsValuesShapesAndMetadata) {
  SafeTensorsWriter writer;
  writer.set_metadata("format_version", "1");
  writer.set_metadata("width", "128");
  writer.add("conv.weight", {2, 1, 3, 3}, std::vector<float>{1, -2, 3.5f, 4, 5, 6, 7, 8, 9, -0.0f,
                                                             1e-30f, 3e30f, 13, 14, 15, 16, 17, 18});
  writer.add("bn.running_var", {3}, {0.5f, 0.25f, 2.0f});
  writer.add("scalar", {}, {42.0f});
  const auto bytes = writer.serialize();
  SafeTensors st = SafeTensors::parse(bytes.data(), bytes.size(), "memory");
  EXPECT_EQ(st.metadata().at("width"), "128");
  EXPECT_EQ(st.names(), (std::vector<std::string>{"bn.running_var", "conv.weight", "scalar"}));
  EXPECT_EQ(st.entry("conv.weight").shape, (std::vector<int64_t>{2, 1, 3, 3}));
  EXPECT_EQ(st.floats("conv.weight")[2], 3.5f);
  EXPECT_EQ(st.floats("conv.weight")[11], 3e30f);
  EXPECT_EQ(st.floats("bn.running_var"), (std::vector<float>{0.5f, 0.25f, 2.0f}));
  EXPECT_EQ(st.floats("scalar"), (std::vector<float>{42.0f}));
  // The data section starts 8-byte aligned, as the format recommends.
  uint64_t n = 0;
  for (int i = 7; i >= 0; --i) n = (n << 8) | bytes[i];
  EXPECT_EQ((8 + n) % 8, 0u);
}

TEST(SafeTensors, WritesAtomicallyAndReadsBack) {
  const auto dir = std::filesystem::temp_directory_path() / "facetool_safetensors_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "w.safetensors").string();
  SafeTensorsWriter writer;
  writer.add("a", {2}, {1.0f, 2.0f});
  writer.write_file(path);
  EXPECT_EQ(SafeTensors::read_file(path).floats("a"), (std::vector<float>{1.0f, 2.0f}));
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string(), "w.safetensors");
  std::filesystem::remove_all(dir);
}

TEST(SafeTensors, MissingFileNamesThePath) {
  try {
    SafeTensors::read_file("/nonexistent/model.safetensors");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/model.safetensors"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("no such file"), std::string::npos);
  }
}

TEST(SafeTensors, TruncatedFileIsRefused) {
  SafeTensorsWriter writer;
  writer.add("a", {4}, {1, 2, 3, 4});
  auto bytes = writer.serialize();
  for (size_t keep : {size_t(0), size_t(5), size_t(20), bytes.size() - 1}) {
    std::vector<uint8_t> cut(bytes.begin(), bytes.begin() + keep);
    EXPECT_NE(parse_error(cut), "") << "kept " << keep << " bytes";
  }
  EXPECT_NE(parse_error(std::vector<uint8_t>(bytes.begin(), bytes.end() - 1)).find("truncated"),
            std::string::npos);
}

TEST(SafeTensors, ShapeDisagreeingWithOffsetsIsRefused) {
  auto bytes = make_file(one_tensor("F32", {3}, 0, 8), std::vector<uint8_t>(8));
  EXPECT_NE(parse_error(bytes).find("need"), std::string::npos);
}

TEST(SafeTensors, UnknownAndWrongDtypes) {
  EXPECT_NE(parse_error(make_file(one_tensor("F33", {2}, 0, 8), std::vector<uint8_t>(8)))
                .find("unknown dtype"),
            std::string::npos);
  auto bytes = make_file(one_tensor("F64", {1}, 0, 8), std::vector<uint8_t>(8));
  SafeTensors st = SafeTensors::parse(bytes.data(), bytes.size(), "f64 file");
  try {
    st.floats("w");
    FAIL() << "F64 read as F32";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("F64"), std::string::npos);
  }
}

TEST(SafeTensors, MissingTensorIsNamed) {
  SafeTensorsWriter writer;
  writer.add("present", {1}, {1.0f});
  auto bytes = writer.serialize();
  SafeTensors st = SafeTensors::parse(bytes.data(), bytes.size(), "weights.safetensors");
  try {
    st.floats("absent.weight");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("absent.weight"), std::string::npos);
  }
}

TEST(SafeTensors, AbsurdHeaderSizesAndOffsets) {
  const std::vector<uint8_t> data(16);
  // Header length far beyond the file, and beyond any sane limit.
  EXPECT_NE(parse_error(make_file(one_tensor("F32", {4}, 0, 16), data, 1 << 20)), "");
  EXPECT_NE(parse_error(make_file(one_tensor("F32", {4}, 0, 16), data, INT64_MAX)), "");
  // Offsets past the data, reversed, or overflowing shapes.
  EXPECT_NE(parse_error(make_file(one_tensor("F32", {4}, 8, 24), data)), "");
  EXPECT_NE(parse_error(make_file(one_tensor("F32", {0}, 16, 8), data)), "");
  EXPECT_NE(parse_error(make_file(one_tensor("F32", {int64_t(1) << 62, 16}, 0, 16), data)), "");
  EXPECT_NE(parse_error(make_file(one_tensor("F32", {-4}, 0, 16), data)), "");
  // Two tensors sharing bytes.
  nlohmann::json two = {{"a", {{"dtype", "F32"}, {"shape", {2}}, {"data_offsets", {0, 8}}}},
                        {"b", {{"dtype", "F32"}, {"shape", {2}}, {"data_offsets", {4, 12}}}}};
  EXPECT_NE(parse_error(make_file(two, data)).find("share"), std::string::npos);
  // Not JSON, not an object, metadata of the wrong type.
  std::vector<uint8_t> garbage = {5, 0, 0, 0, 0, 0, 0, 0, '{', '"', 'x', 0xff, '}'};
  EXPECT_NE(parse_error(garbage), "");
  EXPECT_NE(parse_error(make_file(nlohmann::json::array({1, 2}), data)), "");
  EXPECT_NE(parse_error(make_file({{"__metadata__", {{"k", 3}}}}, data)), "");
}

// A header given as raw text, so that it can hold what nlohmann::json cannot (duplicate keys).
std::vector<uint8_t> make_raw_file(const std::string& text, const std::vector<uint8_t>& data) {
  std::vector<uint8_t> out(8 + text.size() + data.size());
  for (int i = 0; i < 8; ++i) out[i] = uint8_t(uint64_t(text.size()) >> (8 * i));
  std::copy(text.begin(), text.end(), out.begin() + 8);
  std::copy(data.begin(), data.end(), out.begin() + 8 + text.size());
  return out;
}

// Issue 10: JSON keeps the last of two equal keys and ignores bytes no tensor names; the
// safetensors format forbids both, so both are refused, at any nesting level.
TEST(SafeTensors, DuplicateKeysAreRefused) {
  const std::vector<uint8_t> data(8);
  const std::string w = R"("w":{"dtype":"F32","shape":[2],"data_offsets":[0,8]})";
  EXPECT_EQ(parse_error(make_raw_file("{" + w + "}", data)), "");  // the control parses
  const std::string twice = parse_error(make_raw_file("{" + w + "," + w + "}", data));
  EXPECT_NE(twice.find("'w' twice"), std::string::npos) << twice;
  const std::string field = parse_error(make_raw_file(
      R"({"w":{"dtype":"F32","shape":[2],"data_offsets":[0,8],"dtype":"F32"}})", data));
  EXPECT_NE(field.find("'dtype' twice"), std::string::npos) << field;
  const std::string meta = parse_error(
      make_raw_file(R"({"__metadata__":{"a":"1","a":"2"},)" + w + "}", data));
  EXPECT_NE(meta.find("'a' twice"), std::string::npos) << meta;
  EXPECT_NE(meta.find("test.safetensors"), std::string::npos) << meta;
}

TEST(SafeTensors, TrailingBytesAndHolesAreRefused) {
  SafeTensorsWriter writer;
  writer.add("a", {2}, {1, 2});
  writer.add("b", {1}, {3});
  std::vector<uint8_t> bytes = writer.serialize();
  EXPECT_EQ(parse_error(bytes), "");
  for (size_t extra : {1, 4, 1000}) {
    std::vector<uint8_t> longer = bytes;
    longer.insert(longer.end(), extra, 0);
    const std::string message = parse_error(longer);
    EXPECT_NE(message.find(std::to_string(extra) + " trailing bytes"), std::string::npos)
        << message;
  }
  // A hole between two tensors.
  nlohmann::json holed = {{"a", {{"dtype", "F32"}, {"shape", {1}}, {"data_offsets", {0, 4}}}},
                          {"b", {{"dtype", "F32"}, {"shape", {1}}, {"data_offsets", {8, 12}}}}};
  EXPECT_NE(parse_error(make_file(holed, std::vector<uint8_t>(12))).find("belong to no tensor"),
            std::string::npos);
}

// Only regular files are read: a folder and an endless device give a clear message at once.
TEST(SafeTensors, FoldersAndDevicesAreRefusedByName) {
  const std::string folder = std::filesystem::temp_directory_path().string();
  try {
    SafeTensors::read_file(folder);
    FAIL() << "a folder was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is a folder"), std::string::npos) << e.what();
  }
  if (!std::filesystem::exists("/dev/zero")) GTEST_SKIP() << "no /dev/zero on this system";
  try {
    SafeTensors::read_file("/dev/zero");
    FAIL() << "/dev/zero was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'/dev/zero' is not a regular file"), std::string::npos)
        << e.what();
  }
}

// Inputs that once crashed or hung the parser under the fuzzer stay here as regressions.
TEST(SafeTensors, FuzzRegressionInputsNeverCrash) {
  const std::filesystem::path dir = FACETOOL_FUZZ_REGRESSIONS;
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << "no regression inputs in " << dir;
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    std::ifstream in(entry.path(), std::ios::binary);
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    try {
      SafeTensors st = SafeTensors::parse(bytes.data(), bytes.size(), entry.path().string());
      for (const auto& name : st.names())
        if (st.entry(name).dtype == "F32") st.floats(name);
    } catch (const Error&) {
    }
    ++count;
  }
  EXPECT_GT(count, 0);
}

}  // namespace
}  // namespace facetool
