// `facetool fit` on the example photos, a picture without a face, a corrupt file and a full
// disk: what is written (normal.exr at the photo's size, unit normals, zero off the face), the
// exit status and messages as `infer` gives them, --shard, and `infer --with-fit`.
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "libs/face/face_detector.h"
#include "libs/io/exr_io.h"
#include "libs/io/image_io.h"

namespace fs = std::filesystem;

namespace facetool {
namespace {

int run(const std::string& args, const std::string& log) {
  const std::string command = std::string(FACETOOL_EXE) + " " + args + " >/dev/null 2>" + log;
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class FitCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    model_ = std::string(FACETOOL_SHARED_DIR) + "/assets/ict-facekit/FaceXModel";
    if (!fs::exists(model_)) GTEST_SKIP() << "needs ../shared/assets/ict-facekit/FaceXModel; not found at " << model_;
    if (!fs::exists(kDefaultLandmarkModel))
      GTEST_SKIP() << "dlib's landmark model " << kDefaultLandmarkModel << " is not installed (libdlib-data)";
    dir_ = fs::temp_directory_path() / ("facetool_fit_cli_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_ / "photos");
    for (const char* name : {"astronaut.png", "grace_hopper_512x512.jpg"})
      fs::copy_file(fs::path(FACETOOL_EXAMPLES_DIR) / "photos" / name, dir_ / "photos" / name);
    RgbImage plain;  // no face: a smooth pattern
    plain.width = 200;
    plain.height = 150;
    plain.pixels.resize(200 * 150 * 3);
    for (size_t i = 0; i < plain.pixels.size(); ++i) plain.pixels[i] = 0.3f + 0.2f * std::sin(i * 0.001f);
    write_png_atomically((dir_ / "photos" / "wall.png").string(), plain);
  }
  void TearDown() override {
    if (!dir_.empty()) {
      ::umount((dir_ / "disk").c_str());
      fs::remove_all(dir_);
    }
  }
  std::string at(const std::string& name) const { return (dir_ / name).string(); }
  std::string fit_args() const { return "fit --face-model " + model_ + " --directions 64 "; }
  std::string model_;
  fs::path dir_;
};

TEST_F(FitCliTest, FitsEveryExampleAndReportsThePhotoWithout) {
  const int status = run(fit_args() + at("photos") + " -o " + at("out"), at("log"));
  const std::string log = read_text(at("log"));
  EXPECT_EQ(status, 1) << "a photo without a face must make the exit status non-zero: " << log;
  EXPECT_NE(log.find("wall.png': no face found"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "wall"));
  for (const char* stem : {"astronaut", "grace_hopper_512x512"}) {
    const fs::path folder = dir_ / "out" / stem;
    for (const char* file : {"normal.exr", "depth.exr", "visibility.exr", "mask.png", "mesh.obj", "mesh.mtl",
                             "texture.png", "fit.json", "contact_sheet.png"})
      EXPECT_TRUE(fs::is_regular_file(folder / file)) << stem << "/" << file;
    const LayeredImage normal = read_exr((folder / "normal.exr").string());
    ASSERT_EQ(normal.width, 512);
    ASSERT_EQ(normal.height, 512);
    ASSERT_EQ(normal.channel_count(), 3);
    const LayeredImage visibility = read_exr((folder / "visibility.exr").string());
    EXPECT_EQ(visibility.channel_count(), 9);
    size_t covered = 0, unit = 0, facing = 0;
    for (size_t p = 0; p < normal.plane_size(); ++p) {
      const float x = normal.plane(0)[p], y = normal.plane(1)[p], z = normal.plane(2)[p];
      if (x == 0 && y == 0 && z == 0) continue;
      ++covered;
      unit += std::abs(std::sqrt(x * x + y * y + z * z) - 1.0f) < 1e-3f;
      facing += z > 0;  // front faces only: every normal seen has +Z (towards the viewer)
    }
    EXPECT_EQ(normal.plane(2)[0], 0.0f) << "the top-left corner is no face";
    EXPECT_GT(covered, 10000u) << stem;
    EXPECT_LT(covered, normal.plane_size() / 2) << stem;
    EXPECT_EQ(unit, covered) << stem;
    EXPECT_GT(facing, covered * 99 / 100) << stem;
    const std::string json = read_text(folder / "fit.json");
    EXPECT_NE(json.find("\"identity\": ["), std::string::npos);
    EXPECT_NE(json.find("\"jawOpen\": "), std::string::npos);
  }
  EXPECT_NE(log.find("per face: fit "), std::string::npos) << log;
}

// Three inputs whose stems collide (a/x, b/x, c/x_2): three folders, none overwritten, whatever
// the order (the names come from unique_output_names over the whole list).
TEST_F(FitCliTest, InputsSharingANameGetDistinctFolders) {
  for (const char* sub : {"a", "b", "c"}) fs::create_directories(dir_ / sub);
  const fs::path photo = dir_ / "photos" / "astronaut.png";
  fs::copy_file(photo, dir_ / "a" / "x.png");
  fs::copy_file(photo, dir_ / "b" / "x.png");
  fs::copy_file(photo, dir_ / "c" / "x_2.png");
  ASSERT_EQ(run(fit_args() + "--no-visibility --no-contact-sheet " + at("a/x.png") + " " + at("b/x.png") + " " +
                    at("c/x_2.png") + " -o " + at("names"),
                at("log")),
            0)
      << read_text(at("log"));
  int folders = 0;
  for (const auto& entry : fs::directory_iterator(dir_ / "names"))
    if (entry.is_directory() && fs::exists(entry.path() / "fit.json")) ++folders;
  EXPECT_EQ(folders, 3) << read_text(at("log"));
}

TEST_F(FitCliTest, ACorruptPhotoIsReportedAndTheOthersFitted) {
  std::ofstream(at("photos/broken.png")) << "not a png";
  const int status = run(fit_args() + "--no-visibility " + at("photos/broken.png") + " " + at("photos/astronaut.png") +
                             " -o " + at("out"), at("log"));
  const std::string log = read_text(at("log"));
  EXPECT_EQ(status, 1) << log;
  EXPECT_NE(log.find("broken.png"), std::string::npos) << log;
  EXPECT_TRUE(fs::is_regular_file(dir_ / "out" / "astronaut" / "normal.exr"));
}

TEST_F(FitCliTest, ShardsSplitTheInputsAndUsageErrorsExitTwo) {
  // Sorted inputs: astronaut, grace_hopper, wall; shard 1/2 holds grace_hopper only.
  EXPECT_EQ(run(fit_args() + "--no-visibility --shard 1/2 " + at("photos") + " -o " + at("out"), at("log")), 0)
      << read_text(at("log"));
  EXPECT_TRUE(fs::is_regular_file(dir_ / "out" / "grace_hopper_512x512" / "normal.exr"));
  EXPECT_FALSE(fs::exists(dir_ / "out" / "astronaut"));
  EXPECT_EQ(run("fit " + at("photos") + " -o " + at("out2"), at("log")), 2);
  EXPECT_NE(read_text(at("log")).find("--face-model"), std::string::npos);
  EXPECT_EQ(run(fit_args() + "--camera fisheye " + at("photos") + " -o " + at("out2"), at("log")), 2);
  EXPECT_EQ(run(fit_args() + "--jaw-weight -1 " + at("photos") + " -o " + at("out2"), at("log")), 2);
  EXPECT_NE(read_text(at("log")).find("--jaw-weight"), std::string::npos) << read_text(at("log"));
  EXPECT_EQ(run("fit --face-model " + at("nowhere") + " " + at("photos") + " -o " + at("out2"), at("log")), 1);
  EXPECT_NE(read_text(at("log")).find("ICT-FaceKit"), std::string::npos) << read_text(at("log"));
}

TEST_F(FitCliTest, AFullDiskFailsClearlyAndKeepsWhatWasThere) {
  fs::create_directories(dir_ / "disk");
  if (::mount("tmpfs", (dir_ / "disk").c_str(), "tmpfs", 0, "size=1m") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (needs root or CAP_SYS_ADMIN)";
  fs::create_directories(dir_ / "disk" / "out" / "astronaut");
  std::ofstream(at("disk/out/astronaut/fit.json")) << "earlier";
  const int status = run(fit_args() + "--no-visibility " + at("photos/astronaut.png") + " -o " + at("disk/out"), at("log"));
  const std::string log = read_text(at("log"));
  EXPECT_NE(status, 0);
  EXPECT_NE(log.find("No space left"), std::string::npos) << log;
  EXPECT_EQ(read_text(dir_ / "disk" / "out" / "astronaut" / "fit.json"), "earlier") << "an earlier file was lost";
  for (const auto& entry : fs::recursive_directory_iterator(dir_ / "disk"))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
}

TEST_F(FitCliTest, InferWithFitWritesTheFitBesideTheNetworksOutput) {
  EXPECT_EQ(run("infer --with-fit --face-model " + model_ + " --directions 16 --init random --width 8 --input-size 64 " +
                    at("photos/astronaut.png") + " -o " + at("out"), at("log")), 0)
      << read_text(at("log"));
  EXPECT_TRUE(fs::is_regular_file(dir_ / "out" / "astronaut" / "normal.png"));
  EXPECT_TRUE(fs::is_regular_file(dir_ / "out" / "astronaut" / "fit" / "normal.exr"));
  EXPECT_TRUE(fs::is_regular_file(dir_ / "out" / "astronaut" / "fit" / "fit.json"));
}

TEST_F(FitCliTest, PseudoLabelFromFitLabelsRealSamples) {
  ASSERT_EQ(run("prepare-real " + at("photos/astronaut.png") + " -o " + at("real"), at("log")), 0) << read_text(at("log"));
  ASSERT_EQ(run("pseudo-label --from fit --face-model " + model_ + " --directions 64 " + at("real/sample_00000000.exr") +
                    " -o " + at("labelled"), at("log")), 0)
      << read_text(at("log"));
  const LayeredImage in = read_exr(at("real/sample_00000000.exr"), "facetool:");
  const LayeredImage out = read_exr(at("labelled/sample_00000000.exr"), "facetool:");
  EXPECT_EQ(out.width, in.width);
  for (const char* channel : {"R", "mask", "albedo.R", "albedo.B", "normal.X", "normal.Z", "visibility.0", "visibility.8"})
    EXPECT_GE(out.find_channel(channel), 0) << channel;
  ASSERT_NE(out.find_metadata("facetool:light_sh"), nullptr);
  std::istringstream light(*out.find_metadata("facetool:light_sh"));
  int numbers = 0;
  double dc = 0;
  for (double v; light >> v; ++numbers)
    if (numbers == 0) dc = v;
  EXPECT_EQ(numbers, 27);
  EXPECT_GT(dc, 0.0) << "the photo is lit: the light's DC term is positive";
  EXPECT_EQ(*out.find_metadata("facetool:pseudo_labels"), "fit");
  EXPECT_EQ(*out.find_metadata("facetool:generator_version"), "facetool-real-1");
  // The fitted mask covers most of the landmark hull, and its normals are unit vectors there.
  const float* hull = in.plane(in.find_channel("mask"));
  const float* mask = out.plane(out.find_channel("mask"));
  const float* nz = out.plane(out.find_channel("normal.Z"));
  double both = 0, inside = 0, fitted = 0, facing = 0;
  for (size_t p = 0; p < out.plane_size(); ++p) {
    inside += hull[p] > 0.5f;
    both += hull[p] > 0.5f && mask[p] > 0.5f;
    fitted += mask[p] > 0.5f;
    facing += mask[p] > 0.5f && nz[p] > 0.0f;  // interpolated normals may tip over at silhouettes
  }
  EXPECT_GT(both, 0.9 * inside);
  EXPECT_GT(facing, 0.97 * fitted);
  // Without landmarks (a plain crop) the fit has nothing to fit: a clear error.
  EXPECT_EQ(run("pseudo-label --from fit --face-model " + model_ + " " + at("photos/astronaut.png") + " -o " + at("x"), at("log")), 1);
  EXPECT_NE(read_text(at("log")).find("facetool:landmarks"), std::string::npos) << read_text(at("log"));
}

TEST_F(FitCliTest, SamePersonSharesTheIdentityAcrossPhotos) {
  ASSERT_EQ(run(fit_args() + "--no-visibility --no-contact-sheet --same-person " + at("photos/astronaut.png") + " " +
                    at("photos/grace_hopper_512x512.jpg") + " -o " + at("out"), at("log")), 0)
      << read_text(at("log"));
  auto identity = [&](const char* stem) {
    const std::string json = read_text(dir_ / "out" / stem / "fit.json");
    const size_t begin = json.find("\"identity\": [");
    return json.substr(begin, json.find(']', begin) - begin);
  };
  EXPECT_EQ(identity("astronaut"), identity("grace_hopper_512x512"));
  EXPECT_GT(identity("astronaut").size(), 100u);
}

}  // namespace
}  // namespace facetool
