// `facetool landmark-normals` end to end: a head fitted to labelled samples of the example photos, then used by infer.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "libs/io/exr_io.h"
#include "libs/model/safetensors.h"

namespace fs = std::filesystem;

namespace facetool {
namespace {

int facetool_run(const std::string& args) {
  const std::string command = std::string(FACETOOL_EXE) + " " + args + " > /dev/null 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The normal every labelled sample gets: what a head fitted to them must predict for their faces.
constexpr float kNormal[3] = {0.48f, -0.36f, 0.8f};

class LandmarkNormalsCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("facetool_landmark_normals_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    // The shipped model's size and framing, as prepare-real makes them for the example photos.
    ASSERT_EQ(facetool_run("prepare-real " + std::string(FACETOOL_SOURCE_DIR) + "/examples/photos --size 96 "
                           "--framing v2 -o " + (dir_ / "real").string()), 0);
    fs::create_directories(dir_ / "labelled");
    for (const auto& entry : fs::directory_iterator(dir_ / "real")) {
      if (entry.path().extension() != ".exr") continue;
      const LayeredImage sample = read_exr(entry.path().string(), "facetool:");
      std::vector<std::string> names = sample.channel_names;
      for (const char* c : {"albedo.R", "albedo.G", "albedo.B", "normal.X", "normal.Y", "normal.Z"}) names.push_back(c);
      for (int j = 0; j < 9; ++j) names.push_back("visibility." + std::to_string(j));
      LayeredImage labelled(sample.width, sample.height, names);
      std::copy(sample.pixels.begin(), sample.pixels.end(), labelled.pixels.begin());
      const int first = sample.channel_count();
      for (size_t p = 0; p < labelled.plane_size(); ++p) {
        for (int c = 0; c < 3; ++c) labelled.plane(first + c)[p] = 0.5f;
        for (int c = 0; c < 3; ++c) labelled.plane(first + 3 + c)[p] = kNormal[c];
        labelled.plane(first + 6)[p] = 1.0f;
      }
      labelled.metadata = sample.metadata;
      std::string light = "1";
      for (int k = 1; k < 27; ++k) light += k % 9 == 0 ? " 1" : " 0";
      labelled.set_metadata("facetool:light_sh", light);
      write_exr_atomically((dir_ / "labelled" / entry.path().filename()).string(), labelled);
    }
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(LandmarkNormalsCli, TheFittedHeadGivesInferItsNormals) {
  const std::string model = std::string(FACETOOL_SOURCE_DIR) + "/models/facetool-v2.safetensors";
  const std::string head = (dir_ / "head.safetensors").string();
  ASSERT_EQ(facetool_run("landmark-normals --data " + (dir_ / "labelled").string() + " --model " + model +
                         " --blend 1 -o " + head),
            0);
  const SafeTensors file = SafeTensors::read_file(head);
  EXPECT_TRUE(file.contains("landmark_normals.weight"));
  EXPECT_TRUE(file.contains("encoder.layer1.conv.weight"));  // the network's tensors kept
  const std::string photo = std::string(FACETOOL_SOURCE_DIR) + "/examples/photos/astronaut.png";
  ASSERT_EQ(facetool_run("infer " + photo + " --model " + head + " --no-contact-sheet -o " + (dir_ / "with").string()), 0);
  ASSERT_EQ(facetool_run("infer " + photo + " --model " + head + " --no-contact-sheet --no-landmark-normals -o " +
                         (dir_ / "without").string()),
            0);
  // The crop's centre, inside the face: the head's normal (the labels'), and the network's without it.
  const LayeredImage with = read_exr((dir_ / "with" / "astronaut" / "face_0" / "normal.exr").string());
  const LayeredImage without = read_exr((dir_ / "without" / "astronaut" / "face_0" / "normal.exr").string());
  const size_t centre = static_cast<size_t>(with.height / 2) * with.width + with.width / 2;
  const float length = std::sqrt(kNormal[0] * kNormal[0] + kNormal[1] * kNormal[1] + kNormal[2] * kNormal[2]);
  double away = 0;
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(with.plane(c)[centre], kNormal[c] / length, 2e-3) << "channel " << c;
    away += std::fabs(without.plane(c)[centre] - kNormal[c] / length);
  }
  EXPECT_GT(away, 0.1) << "the network alone happens to give the labels' normal";
}

TEST_F(LandmarkNormalsCli, RefusesUnlabelledSamplesAndAGridThatDoesNotDivideTheCrop) {
  const std::string model = std::string(FACETOOL_SOURCE_DIR) + "/models/facetool-v2.safetensors";
  EXPECT_EQ(facetool_run("landmark-normals --data " + (dir_ / "real").string() + " --model " + model + " -o " +
                         (dir_ / "x.safetensors").string()),
            1);
  EXPECT_EQ(facetool_run("landmark-normals --data " + (dir_ / "labelled").string() + " --model " + model +
                         " --grid 7 -o " + (dir_ / "x.safetensors").string()),
            2);
  EXPECT_FALSE(fs::exists(dir_ / "x.safetensors"));
}

}  // namespace
}  // namespace facetool
