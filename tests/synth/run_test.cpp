// run_synth: identical files for any thread count and sharding, resume after interruption, and
// no half-written file under a final name. Uses a tessellated sphere, so no ../shared needed.
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/util/atomic_file.h"
#include "libs/io/image_io.h"
#include "libs/synth/synth_runner.h"
#include "core/util/shard.h"
#include "core/util/error.h"
#include "synth_test_support.h"

namespace facetool {
namespace {
namespace fs = std::filesystem;

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

class SynthRun : public ::testing::Test {
 protected:
  void SetUp() override {
    testing::write_text(lights.file("a.txt"), "1 1 1\n0.2 0.1 0\n0.4 0.4 0.4\n0 0.1 0.2\n0 0 0\n0 0 0\n0.1 0.1 0.1\n0 0 0\n0 0 0\n");
    testing::write_text(lights.file("b.txt"), "2 1.5 1\n-0.3 0 0.3\n0.2 0.2 0.2\n0.5 0.4 0.3\n0 0 0\n0 0 0\n0 0 0\n0 0 0\n0.1 0 0\n");
    SynthSettings settings;
    settings.camera.width = settings.camera.height = 32;
    settings.direction_count = 200;
    FaceSource faces;
    faces.mesh = std::make_shared<const FaceMesh>(testing::make_sphere(24, 48));
    generator = std::make_unique<SampleGenerator>(faces, load_light_sources({lights.path()}),
                                                  BackgroundSource(), make_reference_renderer(),
                                                  settings);
  }
  SynthRunReport run(const std::string& out, int threads, int shard = 0, int shards = 1) {
    SynthRunOptions options;
    options.output_dir = out;
    options.count = 7;
    options.seed = 99;
    options.threads = threads;
    options.shard_index = shard;
    options.shard_count = shards;
    return run_synth(*generator, options);
  }
  testing::ScratchDir lights{"synth-run-lights"};
  testing::ScratchDir work{"synth-run"};
  std::unique_ptr<SampleGenerator> generator;
};

TEST_F(SynthRun, SameFilesWhateverTheThreadsAndShards) {
  const std::string one = work.file("one"), two = work.file("two"), sharded = work.file("sharded");
  EXPECT_EQ(run(one, 1).generated, 7);
  EXPECT_EQ(run(two, 3).generated, 7);
  EXPECT_EQ(run(sharded, 2, 0, 2).generated, 4);
  EXPECT_EQ(run(sharded, 1, 1, 2).generated, 3);
  for (int k = 0; k < 7; ++k) {
    const std::string name = sample_file_name(k);
    const std::string reference = read_bytes(one + "/" + name);
    ASSERT_FALSE(reference.empty()) << name;
    EXPECT_EQ(read_bytes(two + "/" + name), reference) << name;
    EXPECT_EQ(read_bytes(sharded + "/" + name), reference) << name;
  }
  EXPECT_TRUE(fs::exists(sharded + "/manifest-0-of-2.tsv"));
  EXPECT_TRUE(fs::exists(sharded + "/manifest-1-of-2.tsv"));
}

TEST_F(SynthRun, ResumesAfterAnInterruption) {
  const std::string out = work.file("resume");
  run(out, 2);
  const std::string kept = read_bytes(out + "/" + sample_file_name(2));
  const std::string removed = read_bytes(out + "/" + sample_file_name(5));
  // An interrupted run: one sample missing, one truncated (a copy from another tool), and a
  // temporary file of a process that no longer exists.
  fs::remove(out + "/" + sample_file_name(5));
  fs::resize_file(out + "/" + sample_file_name(3), 100);
  testing::write_text(out + "/" + sample_file_name(6) + ".tmp-999999999-0", "partial");
  const SynthRunReport report = run(out, 2);
  EXPECT_EQ(report.generated, 2);  // 5 (missing) and 3 (unreadable)
  EXPECT_EQ(report.reused, 5);
  EXPECT_EQ(read_bytes(out + "/" + sample_file_name(2)), kept);
  EXPECT_EQ(read_bytes(out + "/" + sample_file_name(5)), removed);
  EXPECT_FALSE(fs::exists(out + "/" + sample_file_name(6) + ".tmp-999999999-0"));
  std::ifstream manifest(out + "/manifest-0-of-1.tsv");
  int lines = 0;
  for (std::string line; std::getline(manifest, line);) lines += line.rfind("sample_", 0) == 0;
  EXPECT_EQ(lines, 7);
}

TEST_F(SynthRun, RefusesAFolderOfAnotherSeed) {
  const std::string out = work.file("other-seed");
  run(out, 1);
  SynthRunOptions options;
  options.output_dir = out;
  options.count = 3;
  options.seed = 100;
  EXPECT_THROW(run_synth(*generator, options), Error);
}

// Issue 10: a sample cut short after its header (the header reads, the pixels do not) was kept
// as "already present"; now every kept sample must decode completely, and damaged ones are made
// again, identical to the first run's.
TEST_F(SynthRun, SamplesTruncatedAfterTheirHeaderAreRegenerated) {
  const std::string out = work.file("truncated");
  run(out, 2);
  std::vector<std::string> original;
  for (int k = 0; k < 7; ++k) original.push_back(read_bytes(out + "/" + sample_file_name(k)));
  const std::string cut_a = out + "/" + sample_file_name(1);
  const std::string cut_b = out + "/" + sample_file_name(4);
  fs::resize_file(cut_a, original[1].size() - 64);
  fs::resize_file(cut_b, original[4].size() / 2);
  // The damage is past the header: the metadata check alone would keep these files.
  EXPECT_NO_THROW(read_synth_sample_info(cut_a));
  EXPECT_NO_THROW(read_synth_sample_info(cut_b));
  const SynthRunReport report = run(out, 2);
  EXPECT_EQ(report.generated, 2);
  EXPECT_EQ(report.repaired, 2);
  EXPECT_EQ(report.reused, 5);
  for (int k = 0; k < 7; ++k)
    EXPECT_EQ(read_bytes(out + "/" + sample_file_name(k)), original[k]) << k;
}

// Issue 10: a rerun with other settings (here other lights, other visibility directions, other
// sampling ranges) must not reuse the samples silently: it stops, naming the folder and the way
// out, and changes no file; with overwrite it regenerates them with the new settings.
TEST_F(SynthRun, OtherSettingsAreRefusedUnlessOverwriting) {
  const std::string out = work.file("settings");
  run(out, 2);
  std::vector<std::string> original;
  for (int k = 0; k < 7; ++k) original.push_back(read_bytes(out + "/" + sample_file_name(k)));
  const std::string manifest = read_bytes(out + "/manifest-0-of-1.tsv");
  EXPECT_NE(manifest.find("# settings " + generator->settings_fingerprint()), std::string::npos);
  EXPECT_NE(manifest.find("light b.txt"), std::string::npos) << manifest;

  testing::ScratchDir other_lights{"synth-run-other-lights"};
  testing::write_text(other_lights.file("a.txt"), "1 1 1\n0.2 0.1 0\n0.4 0.4 0.4\n0 0.1 0.2\n0 0 0\n0 0 0\n0.1 0.1 0.1\n0 0 0\n0 0 0\n");
  FaceSource faces;
  faces.mesh = std::make_shared<const FaceMesh>(testing::make_sphere(24, 48));
  SynthSettings base;
  base.camera.width = base.camera.height = 32;
  base.direction_count = 200;
  std::vector<std::pair<std::string, std::unique_ptr<SampleGenerator>>> variants;
  variants.emplace_back("fewer lights",
                        std::make_unique<SampleGenerator>(
                            faces, load_light_sources({other_lights.path()}), BackgroundSource(),
                            make_reference_renderer(), base));
  SynthSettings directions = base;
  directions.direction_count = 201;
  variants.emplace_back("other directions", std::make_unique<SampleGenerator>(
                                                faces, load_light_sources({lights.path()}),
                                                BackgroundSource(), make_reference_renderer(),
                                                directions));
  SynthSettings pose = base;
  pose.pose.max_yaw_deg = 10;
  variants.emplace_back("other pose range", std::make_unique<SampleGenerator>(
                                                faces, load_light_sources({lights.path()}),
                                                BackgroundSource(), make_reference_renderer(),
                                                pose));
  for (const auto& [what, other] : variants) {
    EXPECT_NE(other->settings_fingerprint(), generator->settings_fingerprint()) << what;
    SynthRunOptions options;
    options.output_dir = out;
    options.count = 7;
    options.seed = 99;
    try {
      run_synth(*other, options);
      ADD_FAILURE() << what << ": samples of other settings were reused";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(out), std::string::npos) << message;
      EXPECT_NE(message.find("other settings"), std::string::npos) << message;
      EXPECT_NE(message.find("--overwrite"), std::string::npos) << message;
    }
    for (int k = 0; k < 7; ++k)
      EXPECT_EQ(read_bytes(out + "/" + sample_file_name(k)), original[k]) << what << k;
  }
  SynthRunOptions overwrite;
  overwrite.output_dir = out;
  overwrite.count = 7;
  overwrite.seed = 99;
  overwrite.overwrite = true;
  EXPECT_EQ(run_synth(*variants[0].second, overwrite).generated, 7);
  EXPECT_EQ(read_synth_sample_info(out + "/" + sample_file_name(0)).settings,
            variants[0].second->settings_fingerprint());
  EXPECT_EQ(run_synth(*variants[0].second, overwrite).reused, 7);  // now the same settings
}

TEST_F(SynthRun, AFailedWriteLeavesNoFileUnderTheFinalName) {
  const std::string target = work.file("never.exr");
  EXPECT_THROW(write_atomically(target, [](const std::string& temporary) {
                 testing::write_text(temporary, "half");
                 fail("interrupted");
               }),
               Error);
  EXPECT_FALSE(fs::exists(target));
  for (const auto& entry : fs::directory_iterator(work.path()))
    EXPECT_FALSE(is_temporary_file_name(entry.path().filename().string()));
}

TEST_F(SynthRun, ContactSheetHasOneRowPerSample) {
  const std::string out = work.file("sheet");
  SynthRunOptions options;
  options.output_dir = out;
  options.count = 3;
  options.contact_sheet = out + "/sheet.png";
  run_synth(*generator, options);
  const RgbImage sheet = read_rgb_image(out + "/sheet.png");
  EXPECT_EQ(sheet.width, 5 * 32 + 4 * 2);
  EXPECT_EQ(sheet.height, 3 * 32 + 2 * 2);
}

TEST(SynthShard, ParsesAndRejects) {
  int i = -1, n = -1;
  parse_shard("2/5", i, n);
  EXPECT_EQ(i, 2);
  EXPECT_EQ(n, 5);
  for (const char* bad : {"5/5", "-1/3", "1", "a/b", "1/0", "1/2x"})
    EXPECT_THROW(parse_shard(bad, i, n), Error) << bad;
}

}  // namespace
}  // namespace facetool
