// Reading bad inputs: messages name the file and the problem instead of library internals.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "libs/io/exr_io.h"
#include "libs/io/image_io.h"
#include "libs/light/light_formats.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "tests/support/error_text.h"
#include "tests/support/temp_folder_test.h"

namespace facetool {
namespace {
namespace fs = std::filesystem;

// Each test's folder holds an empty subfolder "folder".
class ReadChecks : public testing::TempFolderTest {
 protected:
  void SetUp() override {
    TempFolderTest::SetUp();
    fs::create_directories(dir_ / "folder");
  }
};

using testing::error_text;

TEST_F(ReadChecks, InputFileChecksNameThePathAndTheProblem) {
  const auto check = [](const std::string& path, const std::string& what) {
    return error_text([&] { check_regular_input_file(path, kMaxTextFileBytes, what); });
  };
  const std::string missing = file("missing.png"), folder = file("folder");
  EXPECT_NE(check(missing, "--albedo")
                .find("--albedo '" + missing + "' does not exist (no such file)"),
            std::string::npos);
  EXPECT_NE(check(folder, "--model").find("--model '" + folder + "' is a folder"),
            std::string::npos);
  EXPECT_NE(check("/dev/zero", "--model").find("'/dev/zero' is not a regular file"),
            std::string::npos);
  EXPECT_NE(check("", "--light").find("--light: the file name is empty"), std::string::npos);
  write("ok.txt", "x");
  EXPECT_EQ(check(file("ok.txt"), "light file"), "");
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
       {error_text([&] { read_rgb_image(file("huge.png")); }),
        error_text([&] { read_exr(file("huge.png")); })}) {
    EXPECT_NE(message.find("image '" + file("huge.png") + "' says it is 100000x100000"),
              std::string::npos)
        << message;
    EXPECT_EQ(message.find("EXR"), std::string::npos) << "a PNG called EXR: " << message;
  }
}

TEST_F(ReadChecks, DamagedFilesAreNamedByTheirKind) {
  write("bad.png", "not a picture");
  write("bad.exr", "not a picture");
  const std::string png = error_text([&] { read_exr(file("bad.png")); });
  EXPECT_NE(png.find("cannot read image '" + file("bad.png") + "'"), std::string::npos) << png;
  const std::string exr = error_text([&] { read_exr(file("bad.exr")); });
  EXPECT_NE(exr.find("cannot read EXR '" + file("bad.exr") + "'"), std::string::npos) << exr;
}

TEST_F(ReadChecks, NonFiniteLightsAreBlamedOnTheirFile) {
  write("inf.json",
        R"({"format": "facetool-light", "version": 1, "coefficients": {"r": [1e999, 0, 0, 0, 0, 0,)"
        R"( 0, 0, 0], "g": [1, 0, 0, 0, 0, 0, 0, 0, 0], "b": [1, 0, 0, 0, 0, 0, 0, 0, 0]}})");
  const std::string message = error_text([&] { light::read_light(file("inf.json")); });
  EXPECT_NE(message.find("light file '" + file("inf.json") + "'"), std::string::npos) << message;
  EXPECT_EQ(message.find("json.exception"), std::string::npos) << message;
  const std::string folder = error_text([&] { light::read_light(file("folder")); });
  EXPECT_NE(folder.find("is a folder"), std::string::npos) << folder;
}

}  // namespace
}  // namespace facetool
