// open_image_file's own JPEG and PNG readers against OpenImageIO (the independent reference, which
// read them before): files of every PNG colour type and bit depth, interlaced or not, with a
// transparent colour; JPEGs of every sampling, progressive, grey, CMYK and YCCK; EXIF orientation in
// both byte orders; real photos; and damaged files refused naming the file.
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>
#include <jpeglib.h>
#include <png.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "core/util/error.h"
#include "libs/io/exif_orientation.h"
#include "libs/io/image_file.h"
#include "libs/io/image_io.h"
#include "tests/support/temp_folder_test.h"

#ifndef FACETOOL_SHARED_DIR
#define FACETOOL_SHARED_DIR ""
#endif

namespace facetool {
namespace {

namespace OIIO = OIIO_NAMESPACE;

struct Decoded {
  int width = 0, height = 0, channels = 0, orientation = 1;
  std::vector<float> values;
};

Decoded read_with_openimageio(const std::string& path) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  EXPECT_TRUE(in) << OIIO::geterror();
  Decoded d;
  if (!in) return d;
  d.width = in->spec().width;
  d.height = in->spec().height;
  d.channels = in->spec().nchannels;
  d.orientation = in->spec().get_int_attribute("Orientation", 1);
  d.values.resize(static_cast<size_t>(d.width) * d.height * d.channels);
  EXPECT_TRUE(in->read_image(0, 0, 0, d.channels, OIIO::TypeDesc::FLOAT, d.values.data()));
  return d;
}

Decoded read_with_facetool(const std::string& path) {
  auto reader = open_image_file(path);
  Decoded d;
  d.width = static_cast<int>(reader->header().width);
  d.height = static_cast<int>(reader->header().height);
  d.channels = reader->header().channels;
  d.orientation = reader->header().orientation;
  d.values.resize(static_cast<size_t>(d.width) * d.height * d.channels);
  reader->read_floats(d.values.data());
  return d;
}

// The two decodings agree: size, channels, orientation, and every value within `tolerance`
// (0: bit for bit).
void expect_same(const std::string& path, float tolerance = 0.0f) {
  const Decoded expected = read_with_openimageio(path);
  const Decoded got = read_with_facetool(path);
  ASSERT_EQ(got.width, expected.width) << path;
  ASSERT_EQ(got.height, expected.height) << path;
  ASSERT_EQ(got.channels, expected.channels) << path;
  EXPECT_EQ(got.orientation, expected.orientation) << path;
  for (size_t i = 0; i < got.values.size(); ++i) {
    if (tolerance == 0.0f)
      ASSERT_EQ(std::memcmp(&got.values[i], &expected.values[i], sizeof(float)), 0)
          << path << " value " << i << ": " << got.values[i] << " against " << expected.values[i];
    else
      ASSERT_NEAR(got.values[i], expected.values[i], tolerance) << path << " value " << i;
  }
}

// A TIFF-structured EXIF block holding only Orientation = `value`, in either byte order.
std::vector<uint8_t> exif_block(int value, bool little) {
  auto u16 = [&](std::vector<uint8_t>& b, unsigned v) {
    if (little) b.insert(b.end(), {uint8_t(v & 0xff), uint8_t(v >> 8)});
    else b.insert(b.end(), {uint8_t(v >> 8), uint8_t(v & 0xff)});
  };
  auto u32 = [&](std::vector<uint8_t>& b, uint32_t v) {
    if (little) { u16(b, v & 0xffff); u16(b, v >> 16); }
    else { u16(b, v >> 16); u16(b, v & 0xffff); }
  };
  std::vector<uint8_t> b = little ? std::vector<uint8_t>{'I', 'I'} : std::vector<uint8_t>{'M', 'M'};
  u16(b, 42);
  u32(b, 8);
  u16(b, 1);         // one entry
  u16(b, 0x0112);    // Orientation
  u16(b, 3);         // SHORT
  u32(b, 1);         // one value
  u16(b, static_cast<unsigned>(value));
  u16(b, 0);
  u32(b, 0);         // no next directory
  return b;
}

// Pixels that exercise every value of a sample depth: a pattern of the position and a seed.
uint32_t sample(size_t i, int depth, uint32_t seed) {
  const uint32_t max = (1u << depth) - 1;
  return static_cast<uint32_t>((i * 2654435761u + seed * 40503u + (i >> 5)) % (max + 1));
}

struct PngSettings {
  int color_type = PNG_COLOR_TYPE_RGB;
  int depth = 8;
  bool interlaced = false;
  bool transparent = false;  // a tRNS chunk
  bool gamma = false;        // a gAMA chunk of 1.0
  int orientation = 0;       // an eXIf chunk when 1-8
};

void write_png_file(const std::string& path, int width, int height, const PngSettings& s) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  ASSERT_NE(file, nullptr);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  ASSERT_FALSE(setjmp(png_jmpbuf(png)));
  png_init_io(png, file);
  png_set_IHDR(png, info, width, height, s.depth, s.color_type,
               s.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  std::vector<png_color> palette;
  if (s.color_type == PNG_COLOR_TYPE_PALETTE) {
    for (int k = 0; k < (1 << s.depth); ++k)
      palette.push_back({static_cast<png_byte>(k * 37), static_cast<png_byte>(255 - k * 11), static_cast<png_byte>(k * 5)});
    png_set_PLTE(png, info, palette.data(), static_cast<int>(palette.size()));
  }
  if (s.transparent) {
    if (s.color_type == PNG_COLOR_TYPE_PALETTE) {
      png_byte alpha[2] = {0, 128};
      png_set_tRNS(png, info, alpha, 2, nullptr);
    } else {
      png_color_16 colour{};
      colour.gray = colour.red = static_cast<png_uint_16>(sample(0, s.depth, 1));
      colour.green = static_cast<png_uint_16>(sample(1, s.depth, 1));
      colour.blue = static_cast<png_uint_16>(sample(2, s.depth, 1));
      png_set_tRNS(png, info, nullptr, 0, &colour);
    }
  }
  if (s.gamma) png_set_gAMA_fixed(png, info, 100000);
  std::vector<uint8_t> exif;
  if (s.orientation > 0) {
    exif = exif_block(s.orientation, false);
    png_set_eXIf_1(png, info, static_cast<png_uint_32>(exif.size()), exif.data());
  }
  png_write_info(png, info);
  const int channels = png_get_channels(png, info);
  const size_t bits_per_row = static_cast<size_t>(width) * channels * s.depth;
  std::vector<std::vector<uint8_t>> rows(height, std::vector<uint8_t>((bits_per_row + 7) / 8));
  for (int y = 0; y < height; ++y)
    for (size_t k = 0; k < static_cast<size_t>(width) * channels; ++k) {
      const uint32_t v = sample(static_cast<size_t>(y) * width * channels + k, s.depth, 7);
      std::vector<uint8_t>& row = rows[y];
      if (s.depth == 16) {
        row[2 * k] = static_cast<uint8_t>(v >> 8);
        row[2 * k + 1] = static_cast<uint8_t>(v & 0xff);
      } else if (s.depth == 8) {
        row[k] = static_cast<uint8_t>(v);
      } else {
        const size_t bit = k * s.depth;
        row[bit / 8] |= static_cast<uint8_t>(v << (8 - s.depth - bit % 8));
      }
    }
  std::vector<png_bytep> pointers;
  for (auto& row : rows) pointers.push_back(row.data());
  png_write_image(png, pointers.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(file);
}

struct JpegSettings {
  J_COLOR_SPACE input = JCS_RGB;  // JCS_RGB, JCS_GRAYSCALE or JCS_CMYK
  J_COLOR_SPACE stored = JCS_YCbCr;
  int h_sampling = 2, v_sampling = 2;  // the first component's
  bool progressive = false;
  int restart_rows = 0;
  int orientation = 0;  // an EXIF APP1 block when 1-8
  bool little_endian_exif = false;
};

void write_jpeg_file(const std::string& path, int width, int height, const JpegSettings& s) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  ASSERT_NE(file, nullptr);
  jpeg_compress_struct info{};
  jpeg_error_mgr errors{};
  info.err = jpeg_std_error(&errors);
  jpeg_create_compress(&info);
  jpeg_stdio_dest(&info, file);
  info.image_width = width;
  info.image_height = height;
  info.input_components = s.input == JCS_GRAYSCALE ? 1 : s.input == JCS_CMYK ? 4 : 3;
  info.in_color_space = s.input;
  jpeg_set_defaults(&info);
  jpeg_set_colorspace(&info, s.stored);
  jpeg_set_quality(&info, 85, TRUE);
  info.comp_info[0].h_samp_factor = s.h_sampling;
  info.comp_info[0].v_samp_factor = s.v_sampling;
  info.restart_in_rows = s.restart_rows;
  if (s.progressive) jpeg_simple_progression(&info);
  jpeg_start_compress(&info, TRUE);
  if (s.orientation > 0) {
    std::vector<uint8_t> app1 = {'E', 'x', 'i', 'f', 0, 0};
    const std::vector<uint8_t> block = exif_block(s.orientation, s.little_endian_exif);
    app1.insert(app1.end(), block.begin(), block.end());
    jpeg_write_marker(&info, JPEG_APP0 + 1, app1.data(), static_cast<unsigned>(app1.size()));
  }
  std::vector<uint8_t> row(static_cast<size_t>(width) * info.input_components);
  while (info.next_scanline < info.image_height) {
    const size_t y = info.next_scanline;
    for (size_t x = 0; x < static_cast<size_t>(width); ++x)
      for (int c = 0; c < info.input_components; ++c)  // smooth gradients and a little noise
        row[x * info.input_components + c] =
            static_cast<uint8_t>((x * (3 + c) * 255 / width + y * (5 - c) * 255 / height + sample(x + y * 7, 4, c)) % 256);
    JSAMPROW pointer = row.data();
    jpeg_write_scanlines(&info, &pointer, 1);
  }
  jpeg_finish_compress(&info);
  jpeg_destroy_compress(&info);
  std::fclose(file);
}

class ImageFileTest : public testing::TempFolderTest {};

TEST_F(ImageFileTest, PngOfEveryColourTypeAndDepthReadsAsOpenImageIoReadsIt) {
  struct Type { int color_type; std::vector<int> depths; };
  const std::vector<Type> types = {{PNG_COLOR_TYPE_GRAY, {1, 2, 4, 8, 16}},
                                   {PNG_COLOR_TYPE_GRAY_ALPHA, {8, 16}},
                                   {PNG_COLOR_TYPE_RGB, {8, 16}},
                                   {PNG_COLOR_TYPE_RGB_ALPHA, {8, 16}},
                                   {PNG_COLOR_TYPE_PALETTE, {1, 2, 4, 8}}};
  int files = 0;
  for (const Type& type : types)
    for (int depth : type.depths)
      for (bool interlaced : {false, true})
        for (bool transparent : {false, true}) {
          if (transparent && (type.color_type & PNG_COLOR_MASK_ALPHA)) continue;
          PngSettings s;
          s.color_type = type.color_type;
          s.depth = depth;
          s.interlaced = interlaced;
          s.transparent = transparent;
          s.gamma = files % 3 == 0;
          const std::string path = file("t" + std::to_string(files++) + ".png");
          write_png_file(path, 13 + files % 5, 7 + files % 3, s);
          expect_same(path);
          EXPECT_EQ(open_image_file(path)->header().format, "png");
          EXPECT_EQ(open_image_file(path)->header().eight_bit, depth <= 8) << path;
        }
  EXPECT_EQ(files, 52);  // 20 grey, 4 grey + alpha, 8 RGB, 4 RGBA, 16 palette
}

TEST_F(ImageFileTest, JpegOfEverySamplingReadsAsOpenImageIoReadsIt) {
  std::vector<JpegSettings> settings;
  for (int h : {1, 2})
    for (int v : {1, 2}) {
      JpegSettings s;
      s.h_sampling = h;
      s.v_sampling = v;
      settings.push_back(s);
    }
  JpegSettings progressive;
  progressive.progressive = true;
  settings.push_back(progressive);
  JpegSettings restarts;
  restarts.restart_rows = 1;
  settings.push_back(restarts);
  JpegSettings grey;
  grey.input = JCS_GRAYSCALE;
  grey.stored = JCS_GRAYSCALE;
  grey.h_sampling = grey.v_sampling = 1;
  settings.push_back(grey);
  JpegSettings rgb;  // stored as RGB, without the YCbCr transform
  rgb.stored = JCS_RGB;
  rgb.h_sampling = rgb.v_sampling = 1;
  settings.push_back(rgb);
  int files = 0;
  for (const JpegSettings& s : settings)
    for (auto [w, h] : {std::pair{1, 1}, std::pair{17, 9}, std::pair{33, 65}}) {
      const std::string path = file("t" + std::to_string(files++) + ".jpg");
      write_jpeg_file(path, w, h, s);
      expect_same(path);
      EXPECT_TRUE(open_image_file(path)->header().eight_bit);
    }
  EXPECT_EQ(files, 24);
}

TEST_F(ImageFileTest, CmykAndYcckJpegsBecomeRgbAsInOpenImageIo) {
  for (J_COLOR_SPACE stored : {JCS_CMYK, JCS_YCCK}) {
    JpegSettings s;
    s.input = JCS_CMYK;
    s.stored = stored;
    s.h_sampling = s.v_sampling = 1;
    const std::string path = file(stored == JCS_CMYK ? "cmyk.jpg" : "ycck.jpg");
    write_jpeg_file(path, 31, 13, s);
    // OpenImageIO multiplies the inks in floats, facetool in integers: the bytes may round apart by one.
    expect_same(path, 1.0f / 255.0f + 1e-6f);
    EXPECT_EQ(open_image_file(path)->header().channels, 3);
  }
}

TEST_F(ImageFileTest, ExifOrientationInJpegAndPngAsOpenImageIoReadsIt) {
  for (int orientation = 1; orientation <= 8; ++orientation) {
    JpegSettings s;
    s.orientation = orientation;
    s.little_endian_exif = orientation % 2 == 0;
    const std::string jpeg = file("o" + std::to_string(orientation) + ".jpg");
    write_jpeg_file(jpeg, 9, 5, s);
    EXPECT_EQ(open_image_file(jpeg)->header().orientation, orientation);
    expect_same(jpeg);
    PngSettings p;
    p.orientation = orientation;
    const std::string png = file("o" + std::to_string(orientation) + ".png");
    write_png_file(png, 9, 5, p);
    EXPECT_EQ(open_image_file(png)->header().orientation, orientation);
    expect_same(png);
  }
  const std::string none = file("none.jpg");
  write_jpeg_file(none, 4, 4, JpegSettings{});
  EXPECT_EQ(open_image_file(none)->header().orientation, 1);
}

TEST(ExifOrientation, DamagedOrUnusualBlocksGiveOne) {
  for (bool little : {true, false}) {
    std::vector<uint8_t> b = exif_block(6, little);
    EXPECT_EQ(exif_orientation(b.data(), b.size()), 6);
    for (size_t cut = 0; cut < 22; ++cut)  // cut anywhere before the entry's end (byte 22)
      EXPECT_EQ(exif_orientation(b.data(), cut), 1) << "cut at " << cut;
    EXPECT_EQ(exif_orientation(b.data(), 22), 6);  // the next directory's offset is not needed
    std::vector<uint8_t> bad = b;
    bad[0] = 'X';  // not a TIFF header
    EXPECT_EQ(exif_orientation(bad.data(), bad.size()), 1);
    bad = exif_block(9, little);  // beyond 1-8
    EXPECT_EQ(exif_orientation(bad.data(), bad.size()), 1);
    bad = exif_block(0, little);
    EXPECT_EQ(exif_orientation(bad.data(), bad.size()), 1);
    bad = b;
    bad[little ? 12 : 13] = 4;  // LONG instead of SHORT
    EXPECT_EQ(exif_orientation(bad.data(), bad.size()), 1);
    bad = b;
    bad[little ? 8 : 9] = 200;  // 200 entries claimed: the walk stops at the block's end
    EXPECT_EQ(exif_orientation(bad.data(), bad.size()), 6);
    bad = b;
    bad[little ? 10 : 11] = 0x13;  // another tag: no orientation
    EXPECT_EQ(exif_orientation(bad.data(), bad.size()), 1);
    bad = b;
    bad[little ? 4 : 7] = 0xf0;  // the directory beyond the block
    EXPECT_EQ(exif_orientation(bad.data(), bad.size()), 1);
  }
  EXPECT_EQ(exif_orientation(nullptr, 0), 1);
}

TEST_F(ImageFileTest, RealPhotosReadAsOpenImageIoReadsThem) {
  std::vector<std::string> photos = {std::string(FACETOOL_EXAMPLES_DIR) + "/photos/grace_hopper_512x512.jpg",
                                     std::string(FACETOOL_EXAMPLES_DIR) + "/photos/astronaut.png"};
  const std::filesystem::path utk = std::filesystem::path(FACETOOL_SHARED_DIR) / "assets/faces/utkface-crop-part1";
  std::error_code ec;
  if (std::filesystem::is_directory(utk, ec)) {
    std::vector<std::string> all;
    for (const auto& entry : std::filesystem::directory_iterator(utk)) all.push_back(entry.path().string());
    std::sort(all.begin(), all.end());
    for (size_t i = 0; i < all.size(); i += 250) photos.push_back(all[i]);
  }
  for (const std::string& photo : photos) {
    expect_same(photo);
    // The photo as the pipeline reads it: read_rgb_image's linear floats from OpenImageIO's.
    const Decoded reference = read_with_openimageio(photo);
    const RgbImage image = read_rgb_image(photo, true);
    for (size_t p = 0; p < image.pixels.size() / 3; ++p)
      for (int c = 0; c < 3; ++c) {
        const float expected = srgb_to_linear(reference.values[p * reference.channels + (reference.channels >= 3 ? c : 0)]);
        ASSERT_EQ(image.pixels[p * 3 + c], expected) << photo << " pixel " << p;
      }
  }
  std::printf("%zu photos compared\n", photos.size());
}

TEST_F(ImageFileTest, TheFormatIsToldByTheBytesNotTheName) {
  write_jpeg_file(file("photo.png"), 8, 8, JpegSettings{});
  EXPECT_EQ(open_image_file(file("photo.png"))->header().format, "jpeg");
  expect_same(file("photo.png"));
  write_png_file(file("photo.jpg"), 8, 8, PngSettings{});
  EXPECT_EQ(open_image_file(file("photo.jpg"))->header().format, "png");
}

// `what` happens to a copy of a good file; reading it must fail with a message naming the file.
void expect_refused(const std::string& path, const std::string& expected_words) {
  try {
    auto reader = open_image_file(path);
    std::vector<float> values(static_cast<size_t>(reader->header().width) * reader->header().height *
                              reader->header().channels);
    reader->read_floats(values.data());
    ADD_FAILURE() << path << " was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(expected_words), std::string::npos) << e.what();
  }
}

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST_F(ImageFileTest, DamagedJpegsAndPngsAreRefusedNamingTheFile) {
  write_jpeg_file(file("good.jpg"), 64, 48, JpegSettings{});
  write_png_file(file("good.png"), 64, 48, PngSettings{});
  const std::string jpeg = bytes_of(file("good.jpg")), png = bytes_of(file("good.png"));
  write("header-only.jpg", jpeg.substr(0, 3));
  expect_refused(file("header-only.jpg"), "not a readable JPEG");
  std::string garbage = jpeg;
  for (size_t i = 20; i < garbage.size(); ++i) garbage[i] = static_cast<char>(i * 7);
  write("garbage.jpg", garbage);
  expect_refused(file("garbage.jpg"), "JPEG");
  write("signature-only.png", png.substr(0, 8));
  expect_refused(file("signature-only.png"), "not a readable PNG");
  std::string bad_header = png;
  bad_header[17] ^= 0x40;  // inside IHDR: its CRC no longer matches
  write("bad-header.png", bad_header);
  expect_refused(file("bad-header.png"), "not a readable PNG");
  write("cut.png", png.substr(0, png.size() / 2));  // cut inside the pixel data
  expect_refused(file("cut.png"), "cannot read the pixels");
  std::string bad_data = png;
  for (size_t i = 50; i < 70 && i < bad_data.size(); ++i) bad_data[i] = static_cast<char>(0xff);
  write("bad-data.png", bad_data);
  expect_refused(file("bad-data.png"), "cannot read the pixels");
}

}  // namespace
}  // namespace facetool
