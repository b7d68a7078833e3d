// The cpu backend's per-machine cache of measured choices, and the fused forward's batch chunk.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

#include "backends/cpu/cpu_conv_choice.h"

namespace facetool::cpu {
namespace {

std::string read_all(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A cache file of its own for one test (FACETOOL_CONV_CACHE), removed afterwards.
class ChoicesFile : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = (std::filesystem::temp_directory_path() /
             ("facetool-choices-" + std::to_string(::getpid()) + ".txt")).string();
    std::filesystem::remove(path_);
    ::setenv("FACETOOL_CONV_CACHE", path_.c_str(), 1);
  }
  void TearDown() override {
    ::unsetenv("FACETOOL_CONV_CACHE");
    std::filesystem::remove(path_);
  }
  std::string path_;
};

TEST_F(ChoicesFile, SavingReplacesThisMachinesKeysAndKeepsEveryOtherLine) {
  {
    std::ofstream out(path_);
    out << "other_cpu/2threads fused_chunk_100B 5\n"
        << conv_machine_name() << " fused_chunk_100B 3\n"
        << conv_machine_name() << " n1_c3_8x8_k3_s1_p1_o4 im2col\n";
  }
  save_fused_chunk(100, 0);
  save_conv_choices({{"n1_c3_8x8_k3_s1_p1_o4", ConvAlgorithm::Winograd}});
  const auto mine = read_machine_choices(path_, conv_machine_name());
  ASSERT_EQ(mine.size(), 2u) << read_all(path_);
  EXPECT_EQ(mine.at("fused_chunk_100B"), "0");
  EXPECT_EQ(mine.at("n1_c3_8x8_k3_s1_p1_o4"), "winograd");
  const auto other = read_machine_choices(path_, "other_cpu/2threads");
  ASSERT_EQ(other.size(), 1u) << read_all(path_);
  EXPECT_EQ(other.at("fused_chunk_100B"), "5");
}

TEST_F(ChoicesFile, NoFileMeansNoChoicesAndAnUnwritablePlaceIsAClearError) {
  EXPECT_TRUE(read_machine_choices(path_, conv_machine_name()).empty());
  EXPECT_TRUE(read_machine_choices("", conv_machine_name()).empty());
  const std::string blocked = path_ + ".file";
  std::ofstream(blocked) << "a file where a folder should be\n";
  const std::string inside = blocked + "/cache.txt";
  ::setenv("FACETOOL_CONV_CACHE", inside.c_str(), 1);
  try {
    save_fused_chunk(100, 2);
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find(inside), std::string::npos) << e.what();
  }
  std::filesystem::remove(blocked);
}

TEST(FusedChunk, TheRuleFillsFourMebibytesWithAtLeastOneImageAndAtMostTheBatch) {
  EXPECT_EQ(default_fused_chunk(int64_t{1} << 20, 20), 4);
  EXPECT_EQ(default_fused_chunk(1179648, 20), 3);  // width 32 at 96 x 96
  EXPECT_EQ(default_fused_chunk(int64_t{8} << 20, 20), 1);
  EXPECT_EQ(default_fused_chunk(1024, 20), 20);
  EXPECT_EQ(default_fused_chunk(1024, 0), 1);
}

TEST(FusedChunk, AnOverrideIsClampedToTheBatchAndZeroMeansTheWholeBatch) {
  set_fused_chunk_override(0);
  EXPECT_EQ(chosen_fused_chunk(1179648, 20), 20);
  EXPECT_EQ(last_fused_chunk_request(), 1179648);
  set_fused_chunk_override(50);
  EXPECT_EQ(chosen_fused_chunk(1179648, 20), 20);
  set_fused_chunk_override(1);
  EXPECT_EQ(chosen_fused_chunk(1179648, 20), 1);
  set_fused_chunk_override(std::nullopt);
  ::setenv("FACETOOL_CONV_CACHE", "", 1);  // no cache: the rule
  EXPECT_EQ(chosen_fused_chunk(1179648, 20), default_fused_chunk(1179648, 20));
  ::unsetenv("FACETOOL_CONV_CACHE");
}

}  // namespace
}  // namespace facetool::cpu
