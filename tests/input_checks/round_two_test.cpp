// Issue 21 (reliability, round two): non-regular files, memory budgets, signals and the
// file-size limit, unique output names, one run per folder, and silently wrong inputs (alpha,
// truncated JPEGs, links, duplicate JSON keys, escape sequences), checked on the shared utilities.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <iterator>
#include <string>
#include <vector>

#include "libs/io/image_io.h"
#include "libs/io/jpeg_check.h"
#include "libs/light/light_formats.h"
#include "libs/model/safetensors.h"
#include "libs/train/training_config.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "core/util/folder_lock.h"
#include "core/util/json_checks.h"
#include "core/util/memory_budget.h"
#include "core/util/output_names.h"
#include "core/util/terminal_text.h"
#include "tests/support/error_text.h"
#include "tests/support/temp_folder_test.h"

namespace facetool {
namespace {
namespace fs = std::filesystem;

using RoundTwo = testing::TempFolderTest;
using testing::error_text;

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Runs `child` in a forked process and returns its exit status (wait()'s raw value); the child
// ends with child()'s return value. For limits (setrlimit) and signals that must not touch the
// test process.
template <typename Child>
int in_child(Child child) {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(child());
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

std::vector<std::string> temporaries_in(const fs::path& dir) {
  std::vector<std::string> found;
  for (const auto& e : fs::directory_iterator(dir))
    if (is_temporary_file_name(e.path().filename().string())) found.push_back(e.path().string());
  return found;
}

// --- class 1: non-regular files --------------------------------------------------------------

// A FIFO given as the training configuration used to block forever in the read; a folder was
// "not valid JSON". Each now gets its own reason, at once.
TEST_F(RoundTwo, ConfigurationPipesFoldersAndFilePathsAreNamedForWhatTheyAre) {
  const std::string fifo = file("config.fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string message = error_text([&] { read_training_config(fifo); });
  EXPECT_TRUE(has(message, "training config '" + fifo + "' is not a regular file")) << message;
  fs::create_directories(file("folder.json"));
  message = error_text([&] { read_training_config(file("folder.json")); });
  EXPECT_TRUE(has(message, "is a folder")) << message;
  EXPECT_FALSE(has(message, "JSON")) << message;
  write("plain.txt", "x");
  message = error_text([&] { read_training_config(file("plain.txt") + "/config.json"); });
  EXPECT_TRUE(has(message, "is a file, not a folder")) << message;
  message = error_text([&] { check_input_folder(file("plain.txt"), "--data"); });
  EXPECT_TRUE(has(message, "--data '" + file("plain.txt") + "' is a file, not a folder")) << message;
  message = error_text([&] { check_input_folder(file("absent"), "--data"); });
  EXPECT_TRUE(has(message, "does not exist")) << message;
  EXPECT_EQ(error_text([&] { check_input_folder(dir_.string(), "--data"); }), "");
}

// Folder listings: regular files are returned; dangling links, link loops and pipes that match
// are reported by name instead of throwing a raw filesystem error or vanishing.
TEST_F(RoundTwo, FolderListingsNameLinksThatLeadNowhere) {
  write("sample_1.exr", "a");
  write("sample_2.exr", "b");
  write("other.txt", "c");
  fs::create_symlink(file("missing.exr"), file("sample_3.exr"));
  fs::create_symlink(file("sample_4.exr"), file("sample_5.exr"));
  fs::create_symlink(file("sample_5.exr"), file("sample_4.exr"));
  ASSERT_EQ(::mkfifo(file("sample_6.exr").c_str(), 0600), 0);
  fs::create_directories(file("sample_7.exr"));  // a folder: not a file, not a problem
  std::vector<std::string> problems;
  const std::vector<std::string> files = list_folder_files(
      dir_.string(), "data", [](const std::string& name) { return name.rfind("sample_", 0) == 0; },
      problems);
  EXPECT_EQ(files, (std::vector<std::string>{file("sample_1.exr"), file("sample_2.exr")}));
  std::string all;
  for (const std::string& p : problems) all += p + "\n";
  EXPECT_EQ(problems.size(), 4u) << all;
  EXPECT_TRUE(has(all, "sample_3.exr' is a dangling symbolic link")) << all;
  EXPECT_TRUE(has(all, "sample_4.exr' is a loop of symbolic links")) << all;
  EXPECT_TRUE(has(all, "sample_5.exr' is a loop of symbolic links")) << all;
  EXPECT_TRUE(has(all, "sample_6.exr' is not a regular file")) << all;
}

// --- class 2: memory ---------------------------------------------------------------------------

uint32_t crc32(const std::string& bytes) {
  uint32_t crc = 0xffffffffu;
  for (unsigned char byte : bytes) {
    crc ^= byte;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return crc ^ 0xffffffffu;
}

std::string big_endian(uint32_t v) { return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)}; }

std::string png_chunk(const std::string& type, const std::string& data) {
  return big_endian(static_cast<uint32_t>(data.size())) + type + data + big_endian(crc32(type + data));
}

// A PNG of `rows` (each already prefixed with its filter byte) in one stored (uncompressed)
// deflate block, so the test needs no zlib.
std::string stored_png(uint32_t width, uint32_t height, char colour_type, const std::string& rows) {
  uint32_t a = 1, b = 0;  // Adler-32
  for (unsigned char byte : rows) {
    a = (a + byte) % 65521;
    b = (b + a) % 65521;
  }
  const uint16_t n = static_cast<uint16_t>(rows.size());
  const std::string zlib = std::string("\x78\x01\x01", 3) + char(n & 0xff) + char(n >> 8) +
                           char(~n & 0xff) + char((~n >> 8) & 0xff) + rows + big_endian((b << 16) | a);
  const std::string ihdr = big_endian(width) + big_endian(height) + std::string(1, '\x08') +
                           std::string(1, colour_type) + std::string(3, '\0');
  return std::string("\x89PNG\r\n\x1a\n", 8) + png_chunk("IHDR", ihdr) + png_chunk("IDAT", zlib) +
         png_chunk("IEND", "");
}

// A 69-byte PNG whose header says 16384 x 16384 (inside the size limits) took 3.3 GB before the
// decoder failed; the header and the file's size alone refuse it now.
TEST_F(RoundTwo, APngHeaderClaimingMorePixelsThanItsBytesIsRefusedBeforeAllocating) {
  const std::string ihdr = big_endian(16384) + big_endian(16384) + std::string("\x08\x02\x00\x00\x00", 5);
  write("claims.png", std::string("\x89PNG\r\n\x1a\n", 8) + png_chunk("IHDR", ihdr) +
                          png_chunk("IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8)) +
                          png_chunk("IEND", ""));
  // Under an address-space limit far below 3.3 GB the old path ended in std::bad_alloc.
  const int status = in_child([&] {
    struct rlimit limit {};
    limit.rlim_cur = limit.rlim_max = rlim_t{1} << 30;
    ::setrlimit(RLIMIT_AS, &limit);
    const std::string message = error_text([&] { read_rgb_image(file("claims.png"), true); });
    return has(message, "16384x16384") && has(message, "too few") ? 0 : 1;
  });
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  // The bound itself: a 1-bit-per-pixel worth of file passes, a tenth of it does not.
  EXPECT_NO_THROW(check_image_header_plausible("x", "png", 16384, 16384, 16384 * 16384 / 8 / 1032));
  EXPECT_THROW(check_image_header_plausible("x", "png", 16384, 16384, 1000), Error);
  EXPECT_NO_THROW(check_image_header_plausible("x", "openexr", 16384, 16384, 1000));
}

// What the memory budget says when an allocation cannot fit under ulimit -v.
TEST_F(RoundTwo, TheMemoryBudgetNamesWhatNeedsHowMuch) {
  const int status = in_child([] {
    struct rlimit limit {};
    limit.rlim_cur = limit.rlim_max = rlim_t{2} << 30;
    ::setrlimit(RLIMIT_AS, &limit);
    if (available_memory_bytes() > (uint64_t{2} << 30)) return 2;
    try {
      check_memory_budget(uint64_t{3} << 30, "reading photo 'x.png'");
    } catch (const OutOfMemory& e) {
      const std::string message = e.what();
      return has(message, "out of memory while reading photo 'x.png' (needs ~3.0 GB)") ? 0 : 3;
    }
    return 4;
  });
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << WEXITSTATUS(status);
  EXPECT_NO_THROW(check_memory_budget(1024, "a small allocation"));
}

// A sparse weights file (a valid header, then gigabytes of holes) was read whole (twice its
// size) before the trailing bytes were refused; the header and the file size refuse it now.
TEST_F(RoundTwo, WeightsWhoseHeaderDoesNotAccountForTheFileAreRefusedUnread) {
  SafeTensorsWriter writer;
  writer.add("w", {4}, {1, 2, 3, 4});
  const std::string path = file("sparse.safetensors");
  writer.write_file(path);
  fs::resize_file(path, fs::file_size(path) + (uint64_t{3} << 30));  // holes: no disk used
  const int status = in_child([&] {
    struct rlimit limit {};
    limit.rlim_cur = limit.rlim_max = rlim_t{1} << 30;  // the old reader needed 6 GB
    ::setrlimit(RLIMIT_AS, &limit);
    const std::string message = error_text([&] { SafeTensors::read_file(path); });
    return has(message, "trailing bytes") && has(message, path) ? 0 : 1;
  });
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  // The control: the same file without the holes reads back.
  fs::resize_file(path, fs::file_size(path) - (uint64_t{3} << 30));
  EXPECT_EQ(SafeTensors::read_file(path).floats("w"), (std::vector<float>{1, 2, 3, 4}));
}

// --- class 3: signals and the file-size limit ----------------------------------------------------

// SIGHUP (or SIGTERM, SIGINT) during a write used to leave "<file>.tmp-PID-N" behind.
TEST_F(RoundTwo, AFatalSignalDuringAWriteLeavesNoTemporary) {
  for (const int signal : {SIGHUP, SIGTERM, SIGINT}) {
    const std::string target = file("out.png");
    const int status = in_child([&] {
      remove_temporaries_on_fatal_signals();
      write_atomically(target, [&](const std::string& temporary) {
        std::ofstream(temporary) << "half";
        ::raise(signal);
      });
      return 0;
    });
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal) << status;
    EXPECT_EQ(temporaries_in(dir_), std::vector<std::string>{}) << "signal " << signal;
    EXPECT_FALSE(fs::exists(target));
  }
}

// Under ulimit -f a write used to kill the process by SIGXFSZ; ignored (as facetool's main
// does), it fails with EFBIG and is reported like a full disk, nothing half-written.
TEST_F(RoundTwo, TheFileSizeLimitIsReportedLikeAFullDisk) {
  write("out.bin", "earlier");
  const int status = in_child([&] {
    std::signal(SIGXFSZ, SIG_IGN);
    struct rlimit limit {};
    limit.rlim_cur = limit.rlim_max = 4096;
    ::setrlimit(RLIMIT_FSIZE, &limit);
    const std::vector<char> big(100000, 'x');
    const std::string message =
        error_text([&] { write_file_atomically(file("out.bin"), big.data(), big.size()); });
    return has(message, "file-size limit") && has(message, "out.bin") ? 0 : 1;
  });
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  EXPECT_EQ(temporaries_in(dir_), std::vector<std::string>{});
  std::ifstream in(file("out.bin"));
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "earlier");
}

// --- class 4: output names -------------------------------------------------------------------

// a/x.png b/x.jpg c/x_2.png used to give x, x_2, x_2: two outputs in one folder. Every order of
// inputs with shared and suffix-like names gives distinct names, a plain name is kept by its
// first holder and an input named like a suffix keeps its own name.
TEST(RoundTwoNames, OutputNamesAreUniqueInEveryOrder) {
  std::vector<std::string> inputs = {"a/x.png", "b/x.jpg", "c/x_2.png", "d/x_3.tif", "e/x_2.png",
                                     "f/y.png"};
  std::sort(inputs.begin(), inputs.end());
  int orders = 0;
  do {
    const std::vector<std::string> names = unique_output_names(inputs);
    ASSERT_EQ(names.size(), inputs.size());
    EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), inputs.size());
    for (size_t k = 0; k < inputs.size(); ++k) {
      const std::string stem = fs::path(inputs[k]).stem().string();
      EXPECT_EQ(names[k].rfind(stem, 0), 0u) << names[k] << " for " << inputs[k];
      if (stem == "y" || stem == "x_3") {
        EXPECT_EQ(names[k], stem);
      }
    }
    ++orders;
  } while (std::next_permutation(inputs.begin(), inputs.end()));
  EXPECT_EQ(orders, 720);
  EXPECT_EQ(unique_output_names({"a/x.png", "b/x.jpg", "c/x_2.png"}),
            (std::vector<std::string>{"x", "x_3", "x_2"}));
  EXPECT_EQ(unique_output_names({"a/s.exr", "b/s.exr"}, true),
            (std::vector<std::string>{"s.exr", "s_2.exr"}));
}

// --- class 6: one run per output folder ---------------------------------------------------------

TEST_F(RoundTwo, OneRunPerOutputFolder) {
  {
    const FolderLock first(dir_.string(), "--out");
    const std::string message = error_text([&] { FolderLock second(dir_.string(), "--out"); });
    EXPECT_TRUE(has(message, "--out '" + dir_.string() + "' is in use by another facetool run"))
        << message;
    // Another process is refused too (flock is per open file, and so per process).
    const int status = in_child([&] {
      return error_text([&] { FolderLock other(dir_.string(), "--out"); }).empty() ? 1 : 0;
    });
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  }
  // Released with its holder; shards share, and exclude an exclusive run.
  EXPECT_EQ(error_text([&] { FolderLock again(dir_.string(), "--out"); }), "");
  const FolderLock shard_0(dir_.string(), "--out", 0, 3);
  EXPECT_EQ(error_text([&] { FolderLock shard_1(dir_.string(), "--out", 1, 3); }), "");
  EXPECT_NE(error_text([&] { FolderLock whole(dir_.string(), "--out"); }), "");
  EXPECT_TRUE(fs::is_empty(dir_));  // no lock file left in the user's folder
}

// Two processes of the same shard wrote the same files: both took the shared lock, so the
// second ran. Now each shard also locks its own byte of the folder: the same shard is refused,
// in this process and in another, and so is a shard of a run split another way; the other
// shards of the run still share the folder, and a shard's slot is free again once it ends.
TEST_F(RoundTwo, OneProcessPerShardOfAnOutputFolder) {
  const std::string folder = dir_.string();
  const FolderLock shard_1(folder, "-o", 1, 3);
  const std::string same = error_text([&] { FolderLock again(folder, "-o", 1, 3); });
  EXPECT_TRUE(has(same, "-o '" + folder + "' is in use by another facetool run of shard 1/3"))
      << same;
  const int status = in_child([&] {
    const bool same_refused = !error_text([&] { FolderLock s(folder, "-o", 1, 3); }).empty();
    const bool split_refused = has(error_text([&] { FolderLock s(folder, "-o", 0, 2); }),
                                   "split into another number of shards");
    const bool other_shard_runs = error_text([&] { FolderLock s(folder, "-o", 2, 3); }).empty();
    const bool whole_refused = !error_text([&] { FolderLock s(folder, "-o"); }).empty();
    return same_refused && split_refused && other_shard_runs && whole_refused ? 0 : 1;
  });
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  {
    const FolderLock shard_0(folder, "-o", 0, 3);
    EXPECT_NE(error_text([&] { FolderLock s(folder, "-o", 0, 3); }), "");
  }
  EXPECT_EQ(error_text([&] { FolderLock s(folder, "-o", 0, 3); }), "");  // released
  EXPECT_TRUE(fs::is_empty(dir_));
}

// --- class 7: silently wrong inputs -------------------------------------------------------------

// docs/photos.md: alpha is dropped. OpenImageIO multiplied the colours by alpha (alpha 128
// darkened the face by half). The PNG is written by hand, so no library decides its meaning.
TEST_F(RoundTwo, AlphaIsDroppedNotMultipliedIn) {
  std::string rows;
  for (int y = 0; y < 2; ++y) {
    rows += '\0';  // filter: none
    for (int x = 0; x < 2; ++x) rows += std::string("\xc8\x64\x32", 3) + char(y == 0 ? 128 : 0);
  }
  write("rgba.png", stored_png(2, 2, '\x06', rows));
  const RgbImage image = read_rgb_image(file("rgba.png"), true);
  ASSERT_EQ(image.width, 2);
  const float expected[3] = {srgb_to_linear(200 / 255.0f), srgb_to_linear(100 / 255.0f),
                             srgb_to_linear(50 / 255.0f)};
  for (size_t p = 0; p < 4; ++p)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(image.pixels[p * 3 + c], expected[c], 1e-6f) << p;
}

// A 64 x 48 JPEG's bytes, written by OpenImageIO to `path` and read back.
std::string jpeg_bytes(const std::string& path) {
  const int w = 64, h = 48;
  std::vector<uint8_t> pixels(static_cast<size_t>(w) * h * 3);
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<uint8_t>((i * 37) % 251);
  auto out = OIIO_NAMESPACE::ImageOutput::create(path);
  EXPECT_TRUE(out && out->open(path, OIIO_NAMESPACE::ImageSpec(w, h, 3, OIIO_NAMESPACE::TypeDesc::UINT8)) &&
              out->write_image(OIIO_NAMESPACE::TypeDesc::UINT8, pixels.data()) && out->close())
      << OIIO_NAMESPACE::geterror();
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// A JPEG cut short decoded with grey rows and no word; now it is refused by name. A complete
// one, also with bytes after its end marker (phones append data), reads as before.
TEST_F(RoundTwo, TruncatedJpegsAreRefused) {
  const std::string whole = jpeg_bytes(file("whole.jpg"));
  ASSERT_GT(whole.size(), 200u);
  write("whole.jpg", whole);
  write("trailer.jpg", whole + "TRAILER DATA \xff\xd8 more");
  write("cut90.jpg", whole.substr(0, whole.size() * 9 / 10));
  write("cut50.jpg", whole.substr(0, whole.size() / 2));
  write("cut_before_end.jpg", whole.substr(0, whole.size() - 2));
  EXPECT_TRUE(jpeg_is_complete(file("whole.jpg")));
  EXPECT_TRUE(jpeg_is_complete(file("trailer.jpg")));
  EXPECT_EQ(error_text([&] { read_rgb_image(file("whole.jpg"), true); }), "");
  EXPECT_EQ(error_text([&] { read_rgb_image(file("trailer.jpg"), true); }), "");
  for (const char* cut : {"cut90.jpg", "cut50.jpg", "cut_before_end.jpg"}) {
    EXPECT_FALSE(jpeg_is_complete(file(cut))) << cut;
    const std::string message = error_text([&] { read_rgb_image(file(cut), true); });
    EXPECT_TRUE(has(message, file(cut)) && has(message, "truncated JPEG")) << message;
  }
}

// A key given twice was accepted (the last one won) in training configurations and light files.
TEST_F(RoundTwo, DuplicateJsonKeysAreRefused) {
  EXPECT_EQ(first_duplicate_json_key(R"({"a": 1, "b": {"a": 2}, "c": [{"a": 1}, {"a": 2}]})"), "");
  EXPECT_EQ(first_duplicate_json_key(R"({"a": 1, "b": {"x": 2, "x": 3}})"), "x");
  EXPECT_EQ(first_duplicate_json_key(R"({"steps": 1, "steps": 2})"), "steps");
  const std::string config =
      R"({"name": "t", "steps": 5, "steps": 500, "sources": [{"name": "s", "directory": "d",)"
      R"( "terms": {"albedo": 1}}]})";
  std::string message = error_text([&] { parse_training_config(config, "c.json"); });
  EXPECT_TRUE(has(message, "c.json") && has(message, "\"steps\" twice")) << message;
  const std::string light =
      R"({"format": "facetool-light", "version": 1, "coefficients": {"r": [1,0,0,0,0,0,0,0,0],)"
      R"( "g": [1,0,0,0,0,0,0,0,0], "b": [1,0,0,0,0,0,0,0,0], "r": [9,0,0,0,0,0,0,0,0]}})";
  write("twice.json", light);
  message = error_text([&] { light::read_light(file("twice.json")); });
  EXPECT_TRUE(has(message, "twice.json") && has(message, "\"r\" twice")) << message;
}

// Class 8 at its source: an Adam epsilon of 0 (0/0 = NaN for a parameter without gradient) and
// a loss weight that is infinite in float are configuration errors naming the key.
TEST(RoundTwoConfig, NonFiniteProducingSettingsAreRefusedByName) {
  auto config = [](const std::string& optimizer, const std::string& weight) {
    return R"({"name": "t", "steps": 5, "optimizer": )" + optimizer +
           R"(, "sources": [{"name": "s", "directory": "d", "terms": {"albedo": )" + weight + "}}]}";
  };
  std::string message = error_text([&] { parse_training_config(config(R"({"epsilon": 0})", "1"), "c.json"); });
  EXPECT_TRUE(has(message, "optimizer.epsilon")) << message;
  message = error_text([&] { parse_training_config(config("{}", "1e308"), "c.json"); });
  EXPECT_TRUE(has(message, "terms.albedo has weight 1e+308")) << message;
  EXPECT_EQ(error_text([&] { parse_training_config(config(R"({"epsilon": 1e-8})", "1e6"), "c.json"); }), "");
}

// Bytes of a hostile file quoted in a message reach the terminal as text, not as commands.
TEST(RoundTwoText, ControlBytesArePrintedNotSent) {
  EXPECT_EQ(printable_text("a\x1b]0;title\x07 b\x1b[2J\r\x7f\nc\td"),
            "a\\x1b]0;title\\x07 b\\x1b[2J\\x0d\\x7f\nc\td");
  EXPECT_EQ(printable_text("plain text: ok"), "plain text: ok");
  // Valid UTF-8 passes; bytes outside it (a binary file quoted) are escaped, so the message is
  // valid UTF-8 (Python raises it with its text, not an empty one).
  EXPECT_EQ(printable_text("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x99\x82"), "caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x99\x82");
  EXPECT_EQ(printable_text("a\xff\xfe b\xc3 c\xe2\x82 d\xc0\xaf e\xed\xa0\x80"),
            "a\\xff\\xfe b\\xc3 c\\xe2\\x82 d\\xc0\\xaf e\\xed\\xa0\\x80");
}

}  // namespace
}  // namespace facetool
