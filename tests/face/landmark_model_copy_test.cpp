// The build's copy of dlib's landmark model rebuilds, through dlib, the very bytes of dlib's file;
// copies round-trip and map with aligned arrays; a damaged, stale or foreign copy is never used.
#include <gtest/gtest.h>

#include <dlib/image_processing.h>

#include <sys/stat.h>
#include <sys/time.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <string>

#include "libs/face/face_detector.h"
#include "libs/face/landmark_model_copy.h"
#include "libs/face/landmark_model_dlib.h"

namespace facetool {
namespace {

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

TEST(LandmarkModelCopy, TheBuildsCopyRebuildsDlibsFileByteForByte) {
  if (!std::filesystem::exists(kDefaultLandmarkModel)) GTEST_SKIP() << kDefaultLandmarkModel << " not installed";
  const std::string path = landmark_model_copy_path();
  ASSERT_FALSE(path.empty()) << "no share/facetool/dlib/shape_predictor_68_face_landmarks.copy beside the test";
  const std::optional<LandmarkModelCopy> copy = read_landmark_model_copy(path, kDefaultLandmarkModel);
  ASSERT_TRUE(copy.has_value()) << path << " was not accepted for " << kDefaultLandmarkModel
                                << " (made from another file, or damaged? rebuild)";
  EXPECT_EQ(copy->parts, 68u);
  std::ostringstream rebuilt;
  dlib::serialize(portable::shape_predictor_from_copy(*copy), rebuilt);
  const std::string dlibs = file_bytes(kDefaultLandmarkModel);
  EXPECT_EQ(rebuilt.str().size(), dlibs.size());
  EXPECT_TRUE(rebuilt.str() == dlibs) << "the predictor built from the copy serialises to other bytes than dlib's file";
}

// A small random model: 3 parts, 2 cascade levels of 4 trees of depth 2, 5 pixels per level.
LandmarkModelCopy random_copy() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(-1, 1);
  LandmarkModelCopy c;
  c.parts = 3, c.cascades = 2, c.trees = 4, c.splits = 3, c.pixels = 5;
  for (uint32_t i = 0; i < 2 * c.parts; ++i) c.initial_shape.push_back(value(rng));
  for (uint32_t i = 0; i < 2 * c.cascades * c.pixels; ++i) c.pixel_coordinates.push_back(value(rng));
  for (uint32_t i = 0; i < 2 * c.cascades * c.trees * c.splits; ++i) c.split_pixels.push_back(rng() % c.pixels);
  for (uint32_t i = 0; i < c.cascades * c.trees * c.splits; ++i) c.split_thresholds.push_back(value(rng));
  for (uint32_t i = 0; i < c.cascades * c.trees * c.leaves() * 2 * c.parts; ++i) c.leaf_values.push_back(value(rng));
  return c;
}

class LandmarkModelCopyFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("facetool-landmark-copy-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
    source_ = (dir_ / "model.dat").string();
    copy_path_ = (dir_ / "model.copy").string();
    write_bytes(source_, "stands for dlib's file");
    model_ = random_copy();
    ASSERT_TRUE(model_.consistent());
    write_landmark_model_copy(copy_path_, model_, *landmark_model_source(source_));
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
  std::string source_, copy_path_;
  LandmarkModelCopy model_;
};

TEST_F(LandmarkModelCopyFile, RoundTrips) {
  const std::optional<LandmarkModelCopy> read = read_landmark_model_copy(copy_path_, source_);
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(read->parts, model_.parts);
  EXPECT_EQ(read->cascades, model_.cascades);
  EXPECT_EQ(read->trees, model_.trees);
  EXPECT_EQ(read->splits, model_.splits);
  EXPECT_EQ(read->pixels, model_.pixels);
  EXPECT_EQ(read->initial_shape, model_.initial_shape);
  EXPECT_EQ(read->pixel_coordinates, model_.pixel_coordinates);
  EXPECT_EQ(read->split_pixels, model_.split_pixels);
  EXPECT_EQ(read->split_thresholds, model_.split_thresholds);
  EXPECT_EQ(read->leaf_values, model_.leaf_values);
  // Another spelling of the same source file is the same file.
  EXPECT_TRUE(read_landmark_model_copy(copy_path_, (dir_ / "." / "model.dat").string()).has_value());
}

TEST_F(LandmarkModelCopyFile, MapsAlignedArraysWhateverThePathLength) {
  for (int extra = 0; extra < 4; ++extra) {  // source paths of four lengths: every padding
    const std::string source = (dir_ / ("model" + std::string(extra, 'x') + ".dat")).string();
    write_bytes(source, "stands for dlib's file");
    write_landmark_model_copy(copy_path_, model_, *landmark_model_source(source));
    const std::optional<MappedLandmarkModel> mapped = map_landmark_model_copy(copy_path_, source);
    ASSERT_TRUE(mapped.has_value()) << "path of " << source.size() << " bytes";
    const LandmarkModelArrays& a = mapped->arrays();
    for (const void* p : {static_cast<const void*>(a.initial_shape), static_cast<const void*>(a.pixel_coordinates),
                          static_cast<const void*>(a.split_pixels), static_cast<const void*>(a.split_thresholds),
                          static_cast<const void*>(a.leaf_values)})
      EXPECT_EQ(reinterpret_cast<uintptr_t>(p) % alignof(float), 0u) << "path of " << source.size() << " bytes";
    EXPECT_EQ(a.parts, model_.parts);
    EXPECT_EQ(std::vector<float>(a.leaf_values, a.leaf_values + model_.leaf_values.size()), model_.leaf_values);
    EXPECT_EQ(std::vector<uint32_t>(a.split_pixels, a.split_pixels + model_.split_pixels.size()), model_.split_pixels);
    EXPECT_EQ(std::vector<float>(a.initial_shape, a.initial_shape + model_.initial_shape.size()), model_.initial_shape);
  }
}

TEST_F(LandmarkModelCopyFile, ThroughDlibAndBackIsTheSameModel) {
  std::ostringstream out;
  dlib::serialize(portable::shape_predictor_from_copy(model_), out);
  std::istringstream in(out.str());
  const LandmarkModelCopy back = portable::landmark_model_copy_of(in);
  EXPECT_EQ(back.split_pixels, model_.split_pixels);
  EXPECT_EQ(back.split_thresholds, model_.split_thresholds);
  EXPECT_EQ(back.leaf_values, model_.leaf_values);
  EXPECT_EQ(back.initial_shape, model_.initial_shape);
  ASSERT_EQ(back.pixel_coordinates.size(), model_.pixel_coordinates.size());
  for (size_t i = 0; i < back.pixel_coordinates.size(); ++i)  // anchor + offset: within rounding
    EXPECT_NEAR(back.pixel_coordinates[i], model_.pixel_coordinates[i], 1e-6) << i;
}

TEST_F(LandmarkModelCopyFile, EveryDamagedByteIsRefused) {
  const std::string bytes = file_bytes(copy_path_);
  // Every byte of the header and path, and a sample of the arrays and the checksum.
  for (size_t i = 0; i < bytes.size(); i += (i < 80 ? 1 : 7)) {
    std::string damaged = bytes;
    damaged[i] = static_cast<char>(damaged[i] ^ 0x10);
    write_bytes(copy_path_, damaged);
    EXPECT_FALSE(read_landmark_model_copy(copy_path_, source_).has_value()) << "byte " << i;
  }
  write_bytes(copy_path_, bytes.substr(0, bytes.size() - 1));
  EXPECT_FALSE(read_landmark_model_copy(copy_path_, source_).has_value()) << "truncated";
  write_bytes(copy_path_, bytes + "x");
  EXPECT_FALSE(read_landmark_model_copy(copy_path_, source_).has_value()) << "one byte longer";
  write_bytes(copy_path_, bytes);
  EXPECT_TRUE(read_landmark_model_copy(copy_path_, source_).has_value()) << "the intact copy again";
}

TEST_F(LandmarkModelCopyFile, AStaleOrForeignCopyIsRefused) {
  const std::string other = (dir_ / "other.dat").string();
  write_bytes(other, "stands for dlib's file");
  EXPECT_FALSE(read_landmark_model_copy(copy_path_, other).has_value()) << "a copy of another file";
  EXPECT_FALSE(read_landmark_model_copy(copy_path_, (dir_ / "missing.dat").string()).has_value());
  EXPECT_FALSE(read_landmark_model_copy("", source_).has_value());
  const std::string fifo = (dir_ / "fifo.copy").string();  // a pipe in the copy's place: refused, not waited on
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_FALSE(map_landmark_model_copy(fifo, source_).has_value());
  // The source changed after the copy was made (same size, newer time).
  struct timeval times[2] = {{1000000000, 0}, {2000000000, 0}};
  ASSERT_EQ(::utimes(source_.c_str(), times), 0);
  EXPECT_FALSE(read_landmark_model_copy(copy_path_, source_).has_value()) << "a copy of the file before it changed";
  write_bytes(source_, "stands for dlib's file, edited");
  EXPECT_FALSE(read_landmark_model_copy(copy_path_, source_).has_value()) << "a copy of the file before it grew";
}

TEST(LandmarkModelCopyLayout, InconsistentCopiesAreNotWritten) {
  LandmarkModelCopy c = random_copy();
  c.split_pixels[0] = c.pixels;  // a pixel out of range
  EXPECT_FALSE(c.consistent());
  c = random_copy();
  c.splits = 2;  // 3 leaves: not a full tree
  EXPECT_FALSE(c.consistent());
  c = random_copy();
  c.leaf_values.pop_back();
  EXPECT_FALSE(c.consistent());
  const std::string path = (std::filesystem::temp_directory_path() / "facetool-landmark-copy-bad.copy").string();
  EXPECT_THROW(write_landmark_model_copy(path, c, LandmarkModelSource{"x", 1, 1}), Error);
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace facetool
