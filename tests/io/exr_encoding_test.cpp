// encode_exr against OpenImageIO's EXR reader (OpenEXR): channels given in any order, halves and
// floats, long names, one-pixel and noisy images come back bit for bit with their metadata; the
// run-length stream expands, by a plain decoder written from the format's description, to the
// bytes coded; the files are no larger than OpenEXR's own RLE files; bad names and images larger than
// facetool reads are refused.
#include <gtest/gtest.h>
#include <Imath/half.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/util/error.h"
#include "libs/io/exr_encoding.h"

namespace facetool {
namespace {

namespace OIIO = OIIO_NAMESPACE;

// OpenEXR's RLE decoding, plainly: a record starting with a negative count n copies -n bytes, a
// non-negative one repeats the next byte n + 1 times; then the running sum of (byte - 128) undoes
// the differences and the two halves (even-, odd-numbered bytes) interleave again. Also checks
// the record bounds this encoder promises (runs of 3 to 128, literals of 1 to 127 bytes).
std::vector<unsigned char> rle_decode(const std::vector<unsigned char>& coded, size_t size) {
  std::vector<unsigned char> prepared;
  for (size_t i = 0; i < coded.size();) {
    const int count = static_cast<signed char>(coded[i++]);
    if (count < 0) {
      EXPECT_LE(-count, 127);
      EXPECT_LE(i + static_cast<size_t>(-count), coded.size());
      for (int k = 0; k < -count && i < coded.size(); ++k) prepared.push_back(coded[i++]);
    } else {
      EXPECT_GE(count + 1, 3) << "a run shorter than three bytes";
      EXPECT_LT(i, coded.size());
      if (i < coded.size()) prepared.insert(prepared.end(), count + 1, coded[i++]);
    }
  }
  EXPECT_EQ(prepared.size(), size);
  for (size_t i = 1; i < prepared.size(); ++i)
    prepared[i] = static_cast<unsigned char>(prepared[i - 1] + prepared[i] - 128);
  std::vector<unsigned char> bytes(prepared.size());
  const size_t half = (prepared.size() + 1) / 2;
  for (size_t i = 0; i < prepared.size(); ++i) bytes[i] = prepared[i % 2 == 0 ? i / 2 : half + i / 2];
  return bytes;
}

TEST(ExrEncoding, RunLengthStreamsExpandToTheBytesCoded) {
  std::mt19937 random(7);
  std::vector<std::vector<unsigned char>> inputs = {{5}, {5, 5}, {1, 2, 3}, {9, 9, 9}};
  // Runs and literals around the record limits, in the prepared (differenced) domain: a constant
  // stretch of n bytes becomes n - 1 bytes of 128 after the first.
  for (const size_t n : {2, 3, 4, 127, 128, 129, 130, 255, 256, 257, 300, 1000}) {
    std::vector<unsigned char> constant(n * 2, 42), noise(n), mixed;
    for (auto& b : noise) b = static_cast<unsigned char>(random());
    for (size_t k = 0; k < 4; ++k) {
      mixed.insert(mixed.end(), n, static_cast<unsigned char>(k));
      for (size_t j = 0; j < n; ++j) mixed.push_back(static_cast<unsigned char>(random() % 3));
    }
    inputs.push_back(constant);
    inputs.push_back(noise);
    inputs.push_back(mixed);
  }
  std::vector<unsigned char> pairs;  // runs of exactly two, which stay literal
  for (int k = 0; k < 500; ++k) pairs.insert(pairs.end(), {static_cast<unsigned char>(k), static_cast<unsigned char>(k)});
  inputs.push_back(pairs);
  for (const auto& bytes : inputs) {
    const std::vector<unsigned char> coded = exr_rle_compress(bytes.data(), bytes.size());
    ASSERT_EQ(rle_decode(coded, bytes.size()), bytes) << bytes.size() << " bytes";
  }
  const std::vector<unsigned char> zeros(100000, 0);
  EXPECT_LT(exr_rle_compress(zeros.data(), zeros.size()).size(), 100000u / 60) << "runs are coded as runs";
}

struct Decoded {
  std::vector<std::string> names;
  std::vector<OIIO::TypeDesc> formats;
  std::vector<float> pixels;  // interleaved, in the order of `names`
  std::map<std::string, std::string> strings;
  int width = 0, height = 0;
};

Decoded decode(std::vector<unsigned char> bytes) {
  OIIO::Filesystem::IOMemReader reader(bytes.data(), bytes.size());
  void* proxy = &reader;
  OIIO::ImageSpec config;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  auto in = OIIO::ImageInput::open("memory.exr", &config);
  Decoded d;
  EXPECT_TRUE(in != nullptr) << OIIO::geterror();
  if (!in) return d;
  const OIIO::ImageSpec& spec = in->spec();
  d.width = spec.width;
  d.height = spec.height;
  d.names.assign(spec.channelnames.begin(), spec.channelnames.end());
  for (int c = 0; c < spec.nchannels; ++c) d.formats.push_back(spec.channelformat(c));
  for (const OIIO::ParamValue& p : spec.extra_attribs)
    if (p.type() == OIIO::TypeDesc::STRING) d.strings[p.name().string()] = p.get_string();
  d.pixels.resize(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
  EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, d.pixels.data())) << in->geterror();
  return d;
}

// Bit-equal floats (NaNs compared by bits too).
bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(ExrEncoding, ChannelsComeBackByNameBitForBitInAnyOrderSizeAndLength) {
  std::mt19937 random(3);
  std::uniform_real_distribution<float> value(-4.0f, 4.0f);
  const std::string long_name(40, 'q');  // past the format's 31 bytes: the long-names flag
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {1, 9}, {13, 1}, {33, 17}, {130, 7}}) {
    const size_t n = static_cast<size_t>(w) * h;
    // Given out of order; "noise" defeats the run-length code (raw chunks), "flat" is all runs.
    const std::vector<std::string> names = {"zeta", "B", "noise", "a.1", "flat", long_name, "A"};
    const std::vector<bool> halves = {true, false, false, true, true, false, true};
    std::vector<std::vector<float>> planes(names.size(), std::vector<float>(n));
    for (size_t c = 0; c < names.size(); ++c)
      for (size_t p = 0; p < n; ++p)
        planes[c][p] = names[c] == "flat" ? 0.25f : names[c] == "noise" ? std::ldexp(value(random), -(int)(random() % 40))
                                                                         : std::sin(0.1f * p + c) * 3.0f;
    planes[0][0] = NAN;
    planes[1][n - 1] = -0.0f;
    std::vector<ExrChannel> channels;
    for (size_t c = 0; c < names.size(); ++c) channels.push_back({names[c], planes[c].data(), 1, halves[c]});
    const Decoded d = decode(encode_exr("test.exr", w, h, channels, {{"facetool:source", "a/b c.png"}, {"note", "caf\u00e9, 2 faces"}}));
    ASSERT_EQ(d.width, w);
    ASSERT_EQ(d.height, h);
    ASSERT_EQ(d.names.size(), names.size());
    EXPECT_EQ(d.strings.at("facetool:source"), "a/b c.png");
    EXPECT_EQ(d.strings.at("note"), "caf\u00e9, 2 faces");
    for (size_t c = 0; c < names.size(); ++c) {
      const auto at = std::find(d.names.begin(), d.names.end(), names[c]);
      ASSERT_NE(at, d.names.end()) << names[c];
      const size_t k = static_cast<size_t>(at - d.names.begin());
      EXPECT_EQ(d.formats[k], halves[c] ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT) << names[c];
      for (size_t p = 0; p < n; ++p) {
        const float want = planes[c][p], got = d.pixels[p * names.size() + k];
        if (std::isnan(want)) {
          EXPECT_TRUE(std::isnan(got)) << names[c] << " " << p;
          continue;
        }
        // A half read back is exactly representable, so its half bits are exact too.
        const bool same = halves[c] ? Imath::half(got).bits() == Imath::half(want).bits() : same_bits(got, want);
        ASSERT_TRUE(same) << names[c] << " pixel " << p << ": " << got << " for " << want << " (" << w << " x " << h
                          << ")";
      }
    }
  }
}

TEST(ExrEncoding, StridedChannelsAreReadWhereTheyLie) {
  const int w = 21, h = 11;
  std::vector<float> rgb(static_cast<size_t>(w) * h * 3);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = 0.01f * static_cast<float>(i);
  std::vector<ExrChannel> channels;
  for (int c = 0; c < 3; ++c) channels.push_back({std::string(1, "RGB"[c]), rgb.data() + c, 3, c == 1});
  const Decoded d = decode(encode_exr("rgb.exr", w, h, channels, {}));
  ASSERT_EQ(d.names, (std::vector<std::string>{"R", "G", "B"}));
  for (size_t p = 0; p < static_cast<size_t>(w) * h; ++p)
    for (int c = 0; c < 3; ++c) {
      const float want = rgb[p * 3 + c], got = d.pixels[p * 3 + c];
      if (c == 1)
        ASSERT_EQ(Imath::half(got).bits(), Imath::half(want).bits()) << p;
      else
        ASSERT_EQ(got, want) << p << " " << c;
    }
}

// OpenEXR's own RLE file of the same smooth-and-empty channels (written through OpenImageIO):
// the same code, so the same size up to the header's differences.
TEST(ExrEncoding, FilesAreNoLargerThanOpenExrsOwnRunLengthFiles) {
  const int w = 256, h = 192, channels = 6;
  std::vector<float> interleaved(static_cast<size_t>(w) * h * channels, 0.0f);
  for (int y = 40; y < 150; ++y)
    for (int x = 60; x < 200; ++x)
      for (int c = 0; c < channels; ++c)
        interleaved[(static_cast<size_t>(y) * w + x) * channels + c] = 0.5f + 0.3f * std::sin(0.05f * x + c) * std::cos(0.04f * y);
  std::vector<ExrChannel> ours;
  OIIO::ImageSpec spec(w, h, channels, OIIO::TypeDesc::FLOAT);
  spec.channelnames.clear();
  for (int c = 0; c < channels; ++c) {
    ours.push_back({"layer." + std::to_string(c), interleaved.data() + c, static_cast<size_t>(channels), c >= 2});
    spec.channelnames.push_back("layer." + std::to_string(c));
    spec.channelformats.push_back(c >= 2 ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
  }
  spec.attribute("compression", "rle");
  std::vector<unsigned char> theirs;
  OIIO::Filesystem::IOVecOutput proxy(theirs);
  void* pointer = &proxy;
  spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &pointer);
  auto out = OIIO::ImageOutput::create("openexr");
  ASSERT_TRUE(out && out->open("theirs.exr", spec) && out->write_image(OIIO::TypeDesc::FLOAT, interleaved.data()) &&
              out->close());
  const std::vector<unsigned char> mine = encode_exr("mine.exr", w, h, ours, {});
  EXPECT_LE(mine.size(), theirs.size() + 64) << "OpenEXR's RLE file: " << theirs.size() << " bytes";
  EXPECT_LT(mine.size(), static_cast<size_t>(w) * h * (2 * 4 + 4 * 2) / 3) << "compressed";
}

TEST(ExrEncoding, BadNamesAndOversizedImagesAreRefusedWithTheName) {
  std::vector<float> plane(4, 1.0f);
  auto refused = [&](const std::vector<ExrChannel>& channels,
                     const std::vector<std::pair<std::string, std::string>>& metadata, const std::string& says) {
    try {
      encode_exr("out/photo.exr", 2, 2, channels, metadata);
      ADD_FAILURE() << "accepted; expected: " << says;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("out/photo.exr"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  refused({{"R", plane.data()}, {"R", plane.data()}}, {}, "two channels are named 'R'");
  refused({{"", plane.data()}}, {}, "needs a name");
  refused({{std::string(256, 'x'), plane.data()}}, {}, "longer than 255 bytes");
  refused({{"R", nullptr}}, {}, "channel 'R' has no pixels");
  refused({{"R", plane.data()}}, {{"channels", "x"}}, "'channels' is given twice or is one of the format's own");
  refused({{"R", plane.data()}}, {{"a", "1"}, {"a", "2"}}, "'a' is given twice");
  refused({}, {}, "the image is empty");
  std::vector<ExrChannel> many;
  for (int c = 0; c < 65; ++c) many.push_back({"c" + std::to_string(c), plane.data()});
  refused(many, {}, "2 x 2 pixels with 65 channels is more than facetool reads back");
  std::vector<float> row(32769, 0.0f);
  try {
    encode_exr("out/wide.exr", 32769, 1, {{"R", row.data()}}, {});
    ADD_FAILURE() << "a 32769-pixel-wide image accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("32769 x 1 pixels with 1 channels is more than facetool reads back"),
              std::string::npos) << e.what();
  }
  // 255 bytes is still a name.
  const Decoded d = decode(encode_exr("long.exr", 2, 2, {{std::string(255, 'n'), plane.data()}}, {}));
  ASSERT_EQ(d.names.size(), 1u);
  EXPECT_EQ(d.names[0].size(), 255u);
}

}  // namespace
}  // namespace facetool
