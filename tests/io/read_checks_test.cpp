// Reading bad inputs: messages name the file and the problem instead of library internals.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/io/exr_io.h"
#include "core/io/image_io.h"
#include "core/io/input_file.h"
#include "core/light/light_formats.h"
#include "core/util/error.h"

namespace facetool {
namespace {
namespace fs = std::filesystem;

class ReadChecks : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("facetool_io_read_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "folder");
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  void write(const std::string& name, const std::string& bytes) const {
    std::ofstream(file(name), std::ios::binary) << bytes;
  }
  fs::path dir_;
};

// The message of the facetool::Error `read` throws ("" when it throws nothing or another type).
template <typename Read>
std::string error_of(Read read) {
  try {
    read();
  } catch (const Error& e) {
    return e.what();
  } catch (...) {
    return "(not a facetool::Error)";
  }
  return "";
}

TEST_F(ReadChecks, InputFileChecksNameThePathAndTheProblem) {
  const std::string missing = file("missing.png"), folder = file("folder");
  EXPECT_NE(error_of([&] { check_input_file(missing, "--albedo"); })
                .find("--albedo '" + missing + "' does not exist (no such file)"),
            std::string::npos);
  EXPECT_NE(error_of([&] { check_input_file(folder, "--model"); })
                .find("--model '" + folder + "' is a folder"),
            std::string::npos);
  EXPECT_NE(error_of([&] { check_input_file("/dev/zero", "--model"); })
                .find("'/dev/zero' is not a regular file"),
            std::string::npos);
  write("ok.txt", "x");
  EXPECT_EQ(error_of([&] { check_input_file(file("ok.txt"), "light file"); }), "");
}

// A PNG whose header says 100000 x 100000 (valid CRCs) is refused before any allocation.
TEST_F(ReadChecks, AHugeImageHeaderIsRefusedWithItsSize) {
  const unsigned char png[] = {
      0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44,
      0x52, 0x00, 0x01, 0x86, 0xa0, 0x00, 0x01, 0x86, 0xa0, 0x08, 0x02, 0x00, 0x00, 0x00, 0x27,
      0x30, 0x9c, 0x9f, 0x00, 0x00, 0x00, 0x0c, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0x60,
      0xa0, 0x0c, 0x00, 0x00, 0x00, 0x40, 0x00, 0x01, 0xb7, 0x34, 0x7c, 0xef, 0x00, 0x00, 0x00,
      0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
  write("huge.png", std::string(reinterpret_cast<const char*>(png), sizeof png));
  for (const std::string& message :
       {error_of([&] { read_rgb_image(file("huge.png")); }),
        error_of([&] { read_exr(file("huge.png")); })}) {
    EXPECT_NE(message.find("image '" + file("huge.png") + "' says it is 100000x100000"),
              std::string::npos)
        << message;
    EXPECT_EQ(message.find("EXR"), std::string::npos) << "a PNG called EXR: " << message;
  }
}

TEST_F(ReadChecks, DamagedFilesAreNamedByTheirKind) {
  write("bad.png", "not a picture");
  write("bad.exr", "not a picture");
  const std::string png = error_of([&] { read_exr(file("bad.png")); });
  EXPECT_NE(png.find("cannot read image '" + file("bad.png") + "'"), std::string::npos) << png;
  const std::string exr = error_of([&] { read_exr(file("bad.exr")); });
  EXPECT_NE(exr.find("cannot read EXR '" + file("bad.exr") + "'"), std::string::npos) << exr;
}

TEST_F(ReadChecks, NonFiniteLightsAreBlamedOnTheirFile) {
  write("inf.json",
        R"({"format": "facetool-light", "version": 1, "coefficients": {"r": [1e999, 0, 0, 0, 0, 0,)"
        R"( 0, 0, 0], "g": [1, 0, 0, 0, 0, 0, 0, 0, 0], "b": [1, 0, 0, 0, 0, 0, 0, 0, 0]}})");
  const std::string message = error_of([&] { light::read_light(file("inf.json")); });
  EXPECT_NE(message.find("light file '" + file("inf.json") + "'"), std::string::npos) << message;
  EXPECT_EQ(message.find("json.exception"), std::string::npos) << message;
  const std::string folder = error_of([&] { light::read_light(file("folder")); });
  EXPECT_NE(folder.find("is a folder"), std::string::npos) << folder;
}

}  // namespace
}  // namespace facetool
