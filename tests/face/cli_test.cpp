// `facetool infer` on photos and `facetool prepare-real`: runs the built executable on the
// example photos and a picture without a face; checks what is written and the exit status.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "libs/face/face_crops.h"
#include "libs/face/face_detector.h"
#include "tests/support/cli_run.h"
#include "libs/io/exr_io.h"
#include "libs/io/image_io.h"

namespace fs = std::filesystem;

namespace facetool {
namespace {

int run(const std::string& args, const std::string& log) {
  return testing::run_cli(FACETOOL_EXE, args, log);
}

using testing::read_text;

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

class PhotoCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kDefaultLandmarkModel))
      GTEST_SKIP() << "dlib's landmark model " << kDefaultLandmarkModel << " is not installed (libdlib-data)";
    dir_ = fs::temp_directory_path() / ("facetool_photo_cli_test_" + std::to_string(::getpid()));
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
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  std::string at(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(PhotoCliTest, InferFindsOneFacePerExampleAndReportsThePhotoWithout) {
  const int status = run("infer " + at("photos") + " --init random --width 8 --input-size 64 -o " + at("out"), at("log"));
  EXPECT_EQ(status, 1) << "a photo without a face must make the exit status non-zero";
  const std::string log = read_text(at("log"));
  EXPECT_NE(log.find("wall.png': no face found"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "wall"));
  for (const char* stem : {"astronaut", "grace_hopper_512x512"}) {
    const fs::path folder = dir_ / "out" / stem;
    const std::string faces = read_text(folder / "faces.json");
    EXPECT_EQ(count(faces, "\"folder\""), 1u) << stem << ": " << faces;
    // The detector that found the face and the padding of the search (0.25 of 512).
    EXPECT_EQ(count(faces, "\"found_by\": \"hog\", \"found_turned_deg\": 0, \"padding_px\": 128,"), 1u) << faces;
    EXPECT_EQ(count(faces, "\"landmark_disagreement\": 0.0"), 1u) << faces;  // agreeing fits (below 0.1)
    EXPECT_EQ(count(faces, "\"landmarks_retried\": false"), 1u) << faces;
    EXPECT_EQ(count(faces, "\"brightened\": false"), 1u) << faces;  // evenly lit: the first look
    EXPECT_EQ(count(faces, "\"landmark_box\": \"hog\""), 1u) << faces;  // found by HOG: its own box
    for (const char* file : {"albedo.png", "normal.png", "visibility.png", "shading.png",
                             "reconstruction.png", "photo.exr", "contact_sheet.png",
                             "face_0/input.png", "face_0/normal.exr", "face_0/light.json"})
      EXPECT_TRUE(fs::is_regular_file(folder / file)) << stem << "/" << file;
    const LayeredImage exr = read_exr((folder / "photo.exr").string());
    EXPECT_EQ(exr.width, 512);
    EXPECT_EQ(exr.height, 512);
    const float* alpha = exr.plane(exr.require_channel("A", "photo.exr"));
    const float* nz = exr.plane(exr.require_channel("normal.Z", "photo.exr"));
    EXPECT_EQ(alpha[0], 0.0f);  // the top-left corner is no face
    EXPECT_EQ(nz[0], 0.0f);
    double covered = 0;
    for (size_t p = 0; p < exr.plane_size(); ++p) covered += alpha[p];
    EXPECT_GT(covered, 3000) << stem;  // the face's landmark hull, photo pixels
    EXPECT_LT(covered, 0.5 * exr.plane_size()) << stem;
    // The input is kept as it was (R G B = the photo, sRGB-decoded).
    const RgbImage photo = read_rgb_image((dir_ / "photos" / (std::string(stem) + (stem[0] == 'a' ? ".png" : ".jpg"))).string(), true);
    double worst = 0;
    for (size_t p = 0; p < exr.plane_size(); ++p) worst = std::max(worst, static_cast<double>(std::abs(exr.plane(0)[p] - photo.pixels[p * 3])));
    EXPECT_LT(worst, 1e-6);
    // normal.png: the premultiplied (n + 1) / 2 over the photo's sRGB values, a data layer
    // composited as a * value + (1 - a) * photo at the face's soft edge (the EXR's layer is half
    // floats: within one level).
    const RgbImage normal_png = read_rgb_image((folder / "normal.png").string(), false);
    const float* normal[3] = {exr.plane(exr.require_channel("normal.X", "photo.exr")),
                              exr.plane(exr.require_channel("normal.Y", "photo.exr")), nz};
    int edge = 0, off = 0;
    for (size_t p = 0; p < exr.plane_size(); ++p)
      for (int c = 0; c < 3; ++c) {
        const float a = alpha[p], n = normal[c][p];
        const double expected = 0.5 * (n + a) + (1 - a) * linear_to_srgb(photo.pixels[p * 3 + c]);
        off += std::abs(normal_png.pixels[p * 3 + c] - std::clamp(expected, 0.0, 1.0)) > 1.01 / 255;
        edge += c == 0 && a > 0 && a < 1;
      }
    EXPECT_EQ(off, 0) << stem;
    EXPECT_GT(edge, 100) << stem;  // the soft edge is there to test
    // The contact sheet shows the landmarks: red dots (linear 1, 0.05, 0.05).
    const RgbImage sheet = read_rgb_image((folder / "contact_sheet.png").string(), true);
    int red = 0;
    for (size_t p = 0; p < sheet.pixels.size() / 3; ++p)
      red += std::abs(sheet.pixels[p * 3] - 1.0f) < 0.01f && std::abs(sheet.pixels[p * 3 + 1] - 0.05f) < 0.01f &&
             std::abs(sheet.pixels[p * 3 + 2] - 0.05f) < 0.01f;
    EXPECT_GE(red, 51) << stem;
  }
}

TEST_F(PhotoCliTest, PhotoFilesAreTheSameBytesEncodedOnOneThreadOrTwo) {
  // The photo-level pictures are encoded on the writer's thread and one more when facetool may
  // use two threads (FACETOOL_NUM_THREADS=1: the writer's alone); every file must come out the
  // same, byte for byte, and all of them must be there.
  const std::string args = "infer " + at("photos/grace_hopper_512x512.jpg") + " --init random --width 8 --input-size 64 -o ";
  ASSERT_EQ(std::system(("FACETOOL_NUM_THREADS=1 " + std::string(FACETOOL_EXE) + " " + args + at("one") + " 2>" + at("log")).c_str()), 0)
      << read_text(at("log"));
  ASSERT_EQ(std::system(("FACETOOL_NUM_THREADS=2 " + std::string(FACETOOL_EXE) + " " + args + at("two") + " 2>" + at("log")).c_str()), 0)
      << read_text(at("log"));
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir_ / "one")) {
    if (!entry.is_regular_file()) continue;
    ++files;
    const fs::path other = dir_ / "two" / fs::relative(entry.path(), dir_ / "one");
    ASSERT_TRUE(fs::is_regular_file(other)) << other;
    EXPECT_EQ(read_text(entry.path()), read_text(other)) << fs::relative(entry.path(), dir_ / "one");
  }
  int files_two = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir_ / "two")) files_two += entry.is_regular_file();
  EXPECT_EQ(files, files_two);
  EXPECT_GE(files, 20);  // 8 photo-level files (faces.json, 5 PNGs, photo.exr, contact sheet), 12 of the face
}

// Several photos' faces share the network's batches and are pasted back on the writer's thread
// (PhotoDecomposer::decompose_faces, then assemble per photo): each photo's files must be those
// of the photo run alone (a face's results do not depend on its batch), so no photo gets another's
// faces. Four photos of four different faces (the two examples and their mirror images), so that
// the photos found while the writer is busy wait in one group.
TEST_F(PhotoCliTest, PhotosBatchedTogetherGiveTheFilesOfEachAlone) {
  fs::create_directories(dir_ / "four");
  for (const char* name : {"astronaut.png", "grace_hopper_512x512.jpg"}) {
    const fs::path from = dir_ / "photos" / name;
    fs::copy_file(from, dir_ / "four" / name);
    RgbImage image = read_rgb_image(from.string(), false);  // the sRGB values, written back as they are
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width / 2; ++x)
        for (int c = 0; c < 3; ++c)
          std::swap(*(image.at(x, y) + c), *(image.at(image.width - 1 - x, y) + c));
    write_png_atomically((dir_ / "four" / ("mirrored_" + fs::path(name).stem().string() + ".png")).string(), image,
                         false);
  }
  const std::string model = " --init random --width 8 --input-size 64 -o ";
  ASSERT_EQ(run("infer " + at("four") + model + at("together"), at("log")), 0) << read_text(at("log"));
  int files = 0;
  for (const auto& photo : fs::directory_iterator(dir_ / "four")) {
    ASSERT_EQ(run("infer " + photo.path().string() + model + at("alone"), at("log")), 0) << read_text(at("log"));
    const std::string stem = photo.path().stem().string();
    for (const auto& entry : fs::recursive_directory_iterator(dir_ / "alone" / stem)) {
      if (!entry.is_regular_file()) continue;
      ++files;
      const fs::path relative = fs::relative(entry.path(), dir_ / "alone");
      ASSERT_TRUE(fs::is_regular_file(dir_ / "together" / relative)) << relative;
      EXPECT_EQ(read_text(entry.path()), read_text(dir_ / "together" / relative)) << relative;
    }
  }
  EXPECT_GE(files, 4 * 20);  // 8 photo-level files and 12 of the face, for each photo
}

// Mean |difference| of two planar images over the pixels where `mask` is set.
double mean_difference_in_mask(const std::vector<float>& a, const std::vector<float>& b, int channels,
                               const std::vector<float>& mask) {
  double sum = 0;
  int count = 0;
  for (size_t p = 0; p < mask.size(); ++p)
    if (mask[p] > 0)
      for (int c = 0; c < channels; ++c, ++count) sum += std::abs(a[c * mask.size() + p] - b[c * mask.size() + p]);
  return sum / std::max(count, 1);
}

// `infer --aligned` on a tight crop of a photo finds the face in it and aligns it by its
// landmarks: the crop and the normals come out close to plain `infer` on the whole photo, unlike
// the stretched crop (--stretch, and the fallback when no face is found, which is reported).
TEST_F(PhotoCliTest, AlignedCropIsAlignedByItsLandmarksLikeThePhoto) {
  const std::string photo_path = at("photos/grace_hopper_512x512.jpg");
  const RgbImage photo = read_rgb_image(photo_path, true);
  FaceDetector detector;
  const std::vector<DetectedFace> faces = detector.detect(photo);
  ASSERT_EQ(faces.size(), 1u);
  const int size = 64;
  const std::vector<float> mask = crop_face(photo, faces[0], size, false).mask;
  // The detector's box grown by 7 to 13 % of its size, clipped to the photo (uneven margins, so
  // that the crop's HOG cells do not line up with the photo's).
  const DetectedFace& f = faces[0];
  const int x0 = std::max(0, static_cast<int>(f.left - 0.07 * f.size())), y0 = std::max(0, static_cast<int>(f.top - 0.13 * f.size()));
  const int x1 = std::min(photo.width, static_cast<int>(f.right + 0.11 * f.size()));
  const int y1 = std::min(photo.height, static_cast<int>(f.bottom + 0.09 * f.size()));
  RgbImage tight;
  tight.width = x1 - x0;
  tight.height = y1 - y0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      for (int c = 0; c < 3; ++c) tight.pixels.push_back(photo.at(x, y)[c]);
  fs::create_directories(dir_ / "crops");
  write_png_atomically(at("crops/tight.png"), tight);
  fs::copy_file(dir_ / "photos" / "wall.png", dir_ / "crops" / "wall.png");
  const std::string network = " --init random --width 8 --input-size " + std::to_string(size);
  ASSERT_EQ(run("infer " + photo_path + network + " -o " + at("full"), at("log")), 0) << read_text(at("log"));
  ASSERT_EQ(run("infer --aligned " + at("crops/tight.png") + " " + at("crops/wall.png") + network + " -o " + at("aligned"),
                at("log")), 0) << read_text(at("log"));
  const std::string log = read_text(at("log"));
  EXPECT_NE(log.find("wall.png': no face found"), std::string::npos) << log;
  EXPECT_NE(log.find("stretched to the network's input as it is"), std::string::npos) << log;
  EXPECT_NE(log.find("aligned 1 of 2 crops by their landmarks; 1 stretched"), std::string::npos) << log;
  ASSERT_EQ(run("infer --aligned --stretch " + at("crops/tight.png") + network + " -o " + at("stretched"), at("log")), 0)
      << read_text(at("log"));
  EXPECT_NE(read_text(at("log")).find("stretched 1 crops to the network's input (--stretch)"), std::string::npos);

  auto planar = [](const std::string& path) { return planar_from_rgb(read_rgb_image(path, true)); };
  auto normals = [](const std::string& path) {
    const LayeredImage exr = read_exr(path);
    std::vector<float> out;
    for (const char* c : {"X", "Y", "Z"}) {
      const float* plane = exr.plane(exr.require_channel(c, path));
      out.insert(out.end(), plane, plane + exr.plane_size());
    }
    return out;
  };
  const std::vector<float> full = planar(at("full/grace_hopper_512x512/face_0/input.png"));
  const double aligned_error = mean_difference_in_mask(full, planar(at("aligned/tight/input.png")), 3, mask);
  const double stretched_error = mean_difference_in_mask(full, planar(at("stretched/tight/input.png")), 3, mask);
  const std::vector<float> full_normal = normals(at("full/grace_hopper_512x512/face_0/normal.exr"));
  const double aligned_normal = mean_difference_in_mask(full_normal, normals(at("aligned/tight/normal.exr")), 3, mask);
  const double stretched_normal = mean_difference_in_mask(full_normal, normals(at("stretched/tight/normal.exr")), 3, mask);
  std::printf("crop mean |diff| from the photo's inside the mask: aligned %.5f, stretched %.4f; normals %.4f, %.4f\n",
              aligned_error, stretched_error, aligned_normal, stretched_normal);
  // Measured: crops 0.017, stretched 0.137; normals 0.16, stretched 0.48. The landmarks of the
  // crop are fitted in another detector box than the photo's (a few pixels apart), and the
  // normals differ more than the crops because the network also sees the crop around the mask,
  // where the tight crop's repeated edge replaces the photo's background.
  EXPECT_LT(aligned_error, 0.03);  // linear RGB
  EXPECT_GT(stretched_error, 0.05);
  EXPECT_LT(aligned_normal, 0.5 * stretched_normal);
}

TEST_F(PhotoCliTest, PrepareRealWritesSamplesResumesAndGivesReasons) {
  ASSERT_EQ(run("prepare-real " + at("photos") + " -o " + at("real"), at("log")), 0) << read_text(at("log"));
  // Sorted: astronaut.png (0), grace_hopper_512x512.jpg (1), wall.png (2, skipped).
  for (int k = 0; k < 2; ++k) {
    const std::string file = at("real/sample_0000000" + std::to_string(k) + ".exr");
    const LayeredImage sample = read_exr(file, "facetool:");
    EXPECT_EQ(sample.width, 128);
    EXPECT_EQ(sample.channel_names, (std::vector<std::string>{"R", "G", "B", "mask"}));
    ASSERT_NE(sample.find_metadata("facetool:generator_version"), nullptr);
    EXPECT_EQ(*sample.find_metadata("facetool:generator_version"), "facetool-real-1");
    EXPECT_EQ(*sample.find_metadata("facetool:source"), k == 0 ? "astronaut.png" : "grace_hopper_512x512.jpg");
    std::istringstream landmarks(*sample.find_metadata("facetool:landmarks")), transform(*sample.find_metadata("facetool:transform"));
    int numbers = 0;
    for (double v; landmarks >> v;) {
      EXPECT_TRUE(v > 0 && v < 128) << v;
      ++numbers;
    }
    EXPECT_EQ(numbers, 136);
    double t[6];
    for (double& v : t) ASSERT_TRUE(transform >> v);
    EXPECT_NEAR(t[0], t[4], 1e-9);   // a similarity: [a -b; b a]
    EXPECT_NEAR(t[1], -t[3], 1e-9);
    double mask = 0;
    for (size_t p = 0; p < sample.plane_size(); ++p) mask += sample.plane(3)[p];
    EXPECT_GT(mask, 500);
  }
  EXPECT_FALSE(fs::exists(at("real/sample_00000002.exr")));
  const std::string manifest = read_text(at("real/manifest.tsv"));
  EXPECT_NE(manifest.find("wall.png\tskipped\tno face found"), std::string::npos) << manifest;

  // Resume: a sample that is there is kept, a missing one is written again, identically.
  const std::string first = read_text(at("real/sample_00000001.exr"));
  const auto kept_time = fs::last_write_time(at("real/sample_00000000.exr"));
  fs::remove(at("real/sample_00000001.exr"));
  ASSERT_EQ(run("prepare-real " + at("photos") + " -o " + at("real"), at("log")), 0);
  EXPECT_EQ(fs::last_write_time(at("real/sample_00000000.exr")), kept_time);
  EXPECT_EQ(read_text(at("real/sample_00000001.exr")), first);
  EXPECT_NE(read_text(at("log")).find("1 written, 1 kept"), std::string::npos) << read_text(at("log"));
}

TEST_F(PhotoCliTest, ExifOrientationIsHonoured) {
  // The astronaut stored turned by 90 degrees with Orientation 8 ("rotate 90 CCW to view") must
  // give the same alignment as the upright file.
  if (std::system("oiiotool --help >/dev/null 2>&1") != 0) GTEST_SKIP() << "oiiotool (openimageio-tools) not found";
  fs::create_directories(dir_ / "turned");
  ASSERT_EQ(std::system(("oiiotool " + at("photos/astronaut.png") + " --rotate90 --attrib Orientation 8 -o " +
                         at("turned/astronaut.tif")).c_str()), 0);
  ASSERT_EQ(run("prepare-real " + at("turned") + " -o " + at("real_turned"), at("log")), 0);
  fs::remove(at("photos/grace_hopper_512x512.jpg"));
  fs::remove(at("photos/wall.png"));
  ASSERT_EQ(run("prepare-real " + at("photos") + " -o " + at("real_upright"), at("log")), 0);
  const LayeredImage a = read_exr(at("real_upright/sample_00000000.exr"), "facetool:");
  const LayeredImage b = read_exr(at("real_turned/sample_00000000.exr"), "facetool:");
  EXPECT_EQ(*a.find_metadata("facetool:transform"), *b.find_metadata("facetool:transform"));
}

TEST_F(PhotoCliTest, GreySixteenBitAndRgbaPhotosAreHandled) {
  if (std::system("oiiotool --help >/dev/null 2>&1") != 0) GTEST_SKIP() << "oiiotool (openimageio-tools) not found";
  fs::create_directories(dir_ / "kinds");
  ASSERT_EQ(std::system(("oiiotool " + at("photos/astronaut.png") + " --ch R --eraseattrib ICCProfile -d uint16 -o " +
                         at("kinds/grey16.png")).c_str()), 0);
  ASSERT_EQ(std::system(("oiiotool " + at("photos/grace_hopper_512x512.jpg") + " --ch R,G,B,A=1.0 -o " +
                         at("kinds/rgba.png")).c_str()), 0);
  ASSERT_EQ(run("prepare-real " + at("kinds") + " -o " + at("real_kinds"), at("log")), 0);
  EXPECT_NE(read_text(at("log")).find("2 written, 0 kept from an earlier run, 0 skipped"), std::string::npos) << read_text(at("log"));
  const LayeredImage grey = read_exr(at("real_kinds/sample_00000000.exr"));
  const size_t plane = grey.plane_size();
  for (size_t p = 0; p < plane; p += 97) {  // grey stays grey: R = G = B
    EXPECT_EQ(grey.plane(0)[p], grey.plane(1)[p]);
    EXPECT_EQ(grey.plane(0)[p], grey.plane(2)[p]);
  }
}

}  // namespace
}  // namespace facetool
