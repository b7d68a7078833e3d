// Atomic writes: nothing under a final name changes unless every file was written completely;
// the encoded PNG and EXR bytes read back (EXR channels stored as half within half precision, with
// Imath::half's rounding bit for bit).
#include <gtest/gtest.h>

#include <Imath/half.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <string>

#include "core/util/atomic_file.h"
#include "libs/io/exr_io.h"
#include "libs/io/image_io.h"
#include "libs/light/light_formats.h"
#include "core/util/error.h"
#include "tests/support/temp_folder_test.h"

namespace facetool {
namespace {
namespace fs = std::filesystem;

class AtomicWrite : public testing::TempFolderTest {
 protected:
  static std::string contents(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream out;
    out << in.rdbuf();
    return out.str();
  }
  std::set<std::string> listing() const {
    std::set<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_)) names.insert(entry.path().filename());
    return names;
  }
};

std::vector<unsigned char> bytes_of(const std::string& text) { return {text.begin(), text.end()}; }

TEST_F(AtomicWrite, FilesThatBelongTogetherAreAllKeptWhenOneCannotBeWritten) {
  write_text_atomically(file("a.txt"), "old a");
  write_text_atomically(file("b.txt"), "old b");
  const std::set<std::string> before = listing();
  const std::string unwritable = file("no_such_folder/c.txt");
  try {
    write_files_atomically({{file("a.txt"), bytes_of("new a")},
                            {file("b.txt"), bytes_of("new b")},
                            {unwritable, bytes_of("c")}});
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(unwritable), std::string::npos) << message;
    EXPECT_NE(message.find(std::strerror(ENOENT)), std::string::npos) << message;
    EXPECT_EQ(message.find(".tmp-"), std::string::npos) << "temporary name shown: " << message;
  }
  EXPECT_EQ(contents(file("a.txt")), "old a");
  EXPECT_EQ(contents(file("b.txt")), "old b");
  EXPECT_EQ(listing(), before) << "a temporary was left behind";

  write_files_atomically({{file("a.txt"), bytes_of("new a")}, {file("b.txt"), bytes_of("new b")}});
  EXPECT_EQ(contents(file("a.txt")), "new a");
  EXPECT_EQ(contents(file("b.txt")), "new b");
  EXPECT_EQ(listing(), before);
}

// A WriteBatch renames nothing before commit(): a failure in the middle of a photo's files
// (here the third cannot be written) leaves every earlier file as it was and no temporary; a
// commit lands all of them; a batch opened inside another joins it.
TEST_F(AtomicWrite, ABatchLandsAllItsFilesAtCommitOrNone) {
  write_text_atomically(file("a.txt"), "old a");
  const std::set<std::string> before = listing();
  try {
    WriteBatch batch;
    write_text_atomically(file("a.txt"), "new a");
    write_text_atomically(file("b.txt"), "new b");
    EXPECT_EQ(contents(file("a.txt")), "old a") << "renamed before the commit";
    EXPECT_FALSE(fs::exists(file("b.txt"))) << "renamed before the commit";
    write_text_atomically(file("no_such_folder/c.txt"), "c");
    batch.commit();
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_folder/c.txt"), std::string::npos) << e.what();
  }
  EXPECT_EQ(contents(file("a.txt")), "old a");
  EXPECT_EQ(listing(), before) << "a temporary or a new file was left behind";

  {
    WriteBatch batch;
    write_text_atomically(file("a.txt"), "new a");
    {
      WriteBatch inner;  // joins the outer batch: its commit lands nothing yet
      write_files_atomically({{file("b.txt"), bytes_of("new b")}});
      inner.commit();
      EXPECT_FALSE(fs::exists(file("b.txt")));
    }
    batch.commit();
  }
  EXPECT_EQ(contents(file("a.txt")), "new a");
  EXPECT_EQ(contents(file("b.txt")), "new b");
  EXPECT_EQ(listing(), (std::set<std::string>{"a.txt", "b.txt"}));
  // Without a batch the writes land at once again.
  write_text_atomically(file("a.txt"), "newer a");
  EXPECT_EQ(contents(file("a.txt")), "newer a");
}

TEST_F(AtomicWrite, AFailureNamesTheFileAndTheSystemsReason) {
  write_text_atomically(file("plain"), "x");
  const std::string below_a_file = file("plain/out.png");
  RgbImage image;
  image.width = image.height = 2;
  image.pixels.assign(12, 0.5f);
  try {
    write_png_atomically(below_a_file, image);
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("cannot write '" + below_a_file + "': " + std::strerror(ENOTDIR)),
              std::string::npos)
        << message;
  }
  EXPECT_EQ(contents(file("plain")), "x");
}

// The in-memory encoders give files OpenImageIO reads back: PNG within one 8-bit step of the
// sRGB encoding, EXR exactly, channel names and metadata kept.
TEST_F(AtomicWrite, EncodedPngAndExrReadBack) {
  RgbImage image;
  image.width = 3;
  image.height = 2;
  for (int k = 0; k < 18; ++k) image.pixels.push_back(static_cast<float>(k) / 17.0f);
  write_png_atomically(file("x.png"), image, false);
  const RgbImage png = read_rgb_image(file("x.png"));
  ASSERT_EQ(png.width, 3);
  ASSERT_EQ(png.height, 2);
  for (size_t k = 0; k < png.pixels.size(); ++k)
    EXPECT_NEAR(png.pixels[k], image.pixels[k], 0.5 / 255 + 1e-6) << k;

  LayeredImage layered(2, 2, {"visibility.0", "visibility.1"});
  for (size_t k = 0; k < layered.pixels.size(); ++k) layered.pixels[k] = 0.1f * k - 0.3f;
  layered.set_metadata("facetool:source", "a test");
  write_exr_atomically(file("x.exr"), layered);
  const LayeredImage exr = read_exr(file("x.exr"), "facetool:");
  EXPECT_EQ(exr.channel_names, layered.channel_names);
  EXPECT_EQ(exr.pixels, layered.pixels);
  ASSERT_EQ(exr.metadata.size(), 1u);
  EXPECT_EQ(exr.metadata[0].second, "a test");
}

TEST_F(AtomicWrite, ExrHalfChannelsReadBackWithinHalfPrecisionAndFloatChannelsExactly) {
  LayeredImage image(37, 23, {"layer.0", "layer.1", "layer.2", "layer.3", "layer.4"});
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> value(-10.0f, 10.0f);
  for (float& v : image.pixels) v = value(rng) * (rng() % 4 == 0 ? 1e-3f : 1.0f);
  std::fill_n(image.plane(4), 40, 0.0f);  // runs of zeros, as outside the faces
  // Channels 0-2 read from an interleaved copy (stride 3), 3-4 from the planes.
  std::vector<float> interleaved(image.plane_size() * 3);
  for (size_t p = 0; p < image.plane_size(); ++p)
    for (int c = 0; c < 3; ++c) interleaved[p * 3 + c] = image.plane(c)[p];
  const bool half[5] = {false, true, false, true, true};
  std::vector<ExrChannel> channels;
  for (int c = 0; c < 5; ++c)
    channels.push_back({image.channel_names[c], c < 3 ? interleaved.data() + c : image.plane(c), c < 3 ? 3u : 1u,
                        half[c]});
  const std::vector<unsigned char> mixed = encode_exr(file("mixed.exr"), 37, 23, channels, {{"facetool:source", "a test"}});
  const std::vector<unsigned char> full = encode_exr(file("full.exr"), image);
  EXPECT_LT(mixed.size(), full.size());
  write_file_atomically(file("mixed.exr"), mixed.data(), mixed.size());
  const LayeredImage back = read_exr(file("mixed.exr"), "facetool:");
  ASSERT_EQ(back.channel_names, image.channel_names);
  ASSERT_EQ(back.metadata.size(), 1u);
  for (int c = 0; c < 5; ++c)
    for (size_t p = 0; p < image.plane_size(); ++p) {
      const float v = image.plane(c)[p], r = back.plane(c)[p];
      if (half[c])  // 10 mantissa bits, rounded: 2^-11 relative (normal halves here)
        EXPECT_NEAR(r, v, std::abs(v) * 0x1p-11f + 1e-7f) << c << " " << p;
      else
        EXPECT_EQ(r, v) << c << " " << p;
    }
  channels[2].data = nullptr;  // a channel without pixels
  EXPECT_THROW(encode_exr(file("bad.exr"), 37, 23, channels, {}), Error);
}

// All of an EXR's metadata read back (prefix "") is what was written, nothing OpenImageIO adds
// ("compression", "oiio:ColorSpace"), so an image read can be written again (pseudo-label does).
TEST_F(AtomicWrite, ExrMetadataReadBackIsWhatWasWrittenAndWritesAgain) {
  LayeredImage image(5, 4, {"u", "v"});
  for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = 0.5f * static_cast<float>(i);
  image.metadata = {{"facetool:source", "x.png"}, {"facetool:faces", "1"}};
  write_exr_atomically(file("first.exr"), image);
  const LayeredImage first = read_exr(file("first.exr"));
  std::set<std::pair<std::string, std::string>> want(image.metadata.begin(), image.metadata.end()),
      got(first.metadata.begin(), first.metadata.end());
  EXPECT_EQ(got, want);
  write_exr_atomically(file("second.exr"), first);
  const LayeredImage second = read_exr(file("second.exr"));
  EXPECT_EQ(second.pixels, image.pixels);
  const std::set<std::pair<std::string, std::string>> again(second.metadata.begin(), second.metadata.end());
  EXPECT_EQ(again, want);
}

// A half channel holds exactly Imath::half's rounding of each float (round to nearest, ties to
// even), whichever path converts it: ties, subnormals, underflow to zero, overflow to infinity,
// negative zero, and random values over the whole exponent range, read from a plane and from an
// interleaved copy.
TEST_F(AtomicWrite, ExrHalfChannelsHoldImathHalfRounding) {
  const int w = 61, h = 37;
  std::vector<float> values = {1.0f + 0x1p-11f, 1.0f + 3 * 0x1p-11f, -(1.0f + 0x1p-11f), 0x1p-20f, 1.5f * 0x1p-24f,
                               0x1p-25f, 0x1p-26f, 65504.0f, 65519.0f, 65520.0f, 70000.0f, -1e9f, -0.0f, 0.0f,
                               2048.0f + 1.0f, 2048.0f + 3.0f, 6.1035156e-05f, 6.0975552e-05f};
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> mantissa(1.0f, 2.0f);
  std::uniform_int_distribution<int> exponent(-30, 18);
  while (values.size() < static_cast<size_t>(w * h))
    values.push_back((rng() % 2 ? -1.0f : 1.0f) * std::ldexp(mantissa(rng), exponent(rng)));
  std::vector<float> interleaved(values.size() * 3, 0.0f);
  for (size_t p = 0; p < values.size(); ++p) interleaved[p * 3 + 1] = values[p];
  const std::vector<ExrChannel> channels = {{"plane", values.data(), 1, true}, {"strided", interleaved.data() + 1, 3, true}};
  const std::vector<unsigned char> bytes = encode_exr(file("halves.exr"), w, h, channels, {});
  write_file_atomically(file("halves.exr"), bytes.data(), bytes.size());
  const LayeredImage back = read_exr(file("halves.exr"), "facetool:");
  ASSERT_EQ(back.channel_count(), 2);
  int differences = 0;
  for (int c = 0; c < 2; ++c)
    for (size_t p = 0; p < values.size(); ++p) {
      // Half bits on both sides (the value read back is a half, so converting it is exact).
      const unsigned short want = Imath::half(values[p]).bits(), got = Imath::half(back.plane(c)[p]).bits();
      if (want != got && ++differences <= 5)
        ADD_FAILURE() << "channel " << c << " value " << values[p] << ": half bits " << got << ", Imath::half gives "
                      << want;
    }
  EXPECT_EQ(differences, 0);
}

TEST_F(AtomicWrite, LightJsonKeysAreInChannelOrder) {
  light::LightFile light;
  for (int k = 0; k < 27; ++k) light.light[k] = 0.1 * k;
  light::write_light(file("light.json"), light, light::Format::Facetool);
  const std::string text = contents(file("light.json"));
  const size_t r = text.find("\"r\""), g = text.find("\"g\""), b = text.find("\"b\"");
  ASSERT_NE(b, std::string::npos) << text;
  EXPECT_LT(r, g) << text;
  EXPECT_LT(g, b) << text;
  const light::LightFile back = light::read_light(file("light.json"));
  for (int k = 0; k < 27; ++k) EXPECT_NEAR(back.light[k], light.light[k], 1e-12) << k;
}

}  // namespace
}  // namespace facetool
