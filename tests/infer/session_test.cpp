// facetool::Session (libs/photo/session.h): the C++ entry object decomposes a photo as `facetool
// infer` does (the same files, byte for byte) and relights it as `facetool relight` does.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "libs/face/face_detector.h"
#include "libs/io/image_io.h"
#include "libs/light/direction_light.h"
#include "libs/photo/photo_files.h"
#include "libs/photo/session.h"

namespace fs = std::filesystem;

namespace facetool {
namespace {

std::string bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class SessionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kDefaultLandmarkModel)) GTEST_SKIP() << "needs dlib's landmark model " << kDefaultLandmarkModel;
    dir_ = fs::temp_directory_path() / ("facetool_session_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  int facetool(const std::string& args) const {
    const std::string command = std::string(FACETOOL_EXE) + " " + args + " 2>" + (dir_ / "stderr.txt").string();
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  fs::path dir_;
};

TEST_F(SessionTest, DecomposesAsInferDoes) {
  const std::string photo_path = std::string(FACETOOL_SOURCE_DIR) + "/examples/photos/grace_hopper_512x512.jpg";
  ASSERT_EQ(facetool("infer " + photo_path + " -o " + (dir_ / "infer").string()), 0) << bytes(dir_ / "stderr.txt");
  Session session;  // the shipped model, infer's defaults
  const DecomposedPhoto photo = session.decompose_file(photo_path);
  ASSERT_EQ(photo.crops.size(), 1u);
  write_photo_files((dir_ / "session").string(), photo, session.framed());
  int compared = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir_ / "infer" / "grace_hopper_512x512")) {
    if (!entry.is_regular_file()) continue;
    const fs::path relative = fs::relative(entry.path(), dir_ / "infer" / "grace_hopper_512x512");
    if (relative == "faces.json") continue;  // names the photo as given on the command line
    SCOPED_TRACE(relative.string());
    ASSERT_TRUE(fs::exists(dir_ / "session" / relative));
    EXPECT_TRUE(bytes(entry.path()) == bytes(dir_ / "session" / relative)) << "differs from infer's";
    ++compared;
  }
  EXPECT_GE(compared, 15);

  // The framing comes from the model: a caller's framing is replaced by the weights'.
  PhotoInferOptions v1;
  v1.framing = v1_framing();
  ASSERT_NE(session.model().framing, v1_framing()) << "the shipped model is framed as v2";
  EXPECT_EQ(session.framed(v1).framing, session.model().framing);

  // Relit as `facetool relight` relights: a light from the viewer's left.
  const sh::RgbLight light = light::light_from_direction(-60, 20, 0.3, 1.0);
  ASSERT_EQ(facetool("relight " + photo_path + " --light-direction -60,20 --ambient 0.3 --intensity 1 -o " +
                     (dir_ / "relit").string()),
            0)
      << bytes(dir_ / "stderr.txt");
  write_png_atomically((dir_ / "session_relit.png").string(), session.relight(photo, light).image);
  fs::path cli_relit;
  for (const auto& entry : fs::recursive_directory_iterator(dir_ / "relit"))
    if (entry.path().filename() == "relit.png") cli_relit = entry.path();
  ASSERT_FALSE(cli_relit.empty());
  EXPECT_TRUE(bytes(cli_relit) == bytes(dir_ / "session_relit.png"));
}

}  // namespace
}  // namespace facetool

namespace facetool {
namespace {

// The paste-back's memory check counts the planes asked for (hand-counted here): the coverage,
// 3 per colour or vector layer, 9 for the visibility, 25 for photo.exr.
TEST(PhotoPlanes, CountOnlyTheLayersAndFilesAskedFor) {
  auto planes = [](const std::string& outputs) {
    PhotoInferOptions o;
    o.outputs = PhotoOutputs::parse(outputs, "--outputs");
    o.layers = o.outputs.layers();
    return photo_planes(o);
  };
  EXPECT_EQ(photo_planes(PhotoInferOptions{}), 47u);
  EXPECT_EQ(planes("all"), 47u);
  EXPECT_EQ(planes("normal"), 4u);
  EXPECT_EQ(planes("albedo,normal"), 7u);
  EXPECT_EQ(planes("visibility"), 10u);
  EXPECT_EQ(planes("faces"), 1u);
  EXPECT_EQ(planes("exr"), 47u);
}

}  // namespace
}  // namespace facetool
