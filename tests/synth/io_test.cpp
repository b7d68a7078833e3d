// libs/io: OBJ parsing (quads, vertex-only files, relative indices, errors) and EXR round trips.
#include <cmath>

#include "libs/io/exr_io.h"
#include "libs/io/image_io.h"
#include "libs/io/obj_reader.h"
#include "core/util/error.h"
#include "synth_test_support.h"

namespace facetool {
namespace {

TEST(ObjReader, TriangulatesPolygonsAndKeepsMaterials) {
  const ObjMesh mesh = parse_obj(
      "# comment\nmtllib x.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nvt 0 0\nvt 1 0\n"
      "vt 1 1\nvt 0 1\ng head\nusemtl skin\nf 1/1 2/2 3/3 4/4\nusemtl teeth\nf -4 -3 -1\n",
      "inline");
  ASSERT_EQ(mesh.positions.size(), 5u);
  ASSERT_EQ(mesh.triangles.size(), 3u);
  EXPECT_EQ(mesh.triangles[0], (std::array<int32_t, 3>{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[1], (std::array<int32_t, 3>{0, 2, 3}));
  EXPECT_EQ(mesh.triangles[2], (std::array<int32_t, 3>{1, 2, 4}));  // relative indices
  EXPECT_EQ(mesh.triangle_texcoords[1], (std::array<int32_t, 3>{0, 2, 3}));
  EXPECT_EQ(mesh.triangle_texcoords[2][0], -1);
  EXPECT_EQ(mesh.triangle_polygon, (std::vector<int32_t>{0, 0, 1}));
  EXPECT_EQ(mesh.materials, (std::vector<std::string>{"skin", "teeth"}));
  EXPECT_EQ(mesh.triangle_material, (std::vector<int32_t>{0, 0, 1}));
  EXPECT_EQ(mesh.groups, (std::vector<std::string>{"head"}));
  EXPECT_EQ(mesh.polygon_count, 2);
}

TEST(ObjReader, VertexOnlyFilesAndNumberFormats) {
  const ObjMesh mesh = parse_obj("v -2.36702e-08 +1.5 3\r\nv 1 2 3 1.0\n", "inline");
  ASSERT_EQ(mesh.positions.size(), 2u);
  EXPECT_TRUE(mesh.triangles.empty());
  EXPECT_FLOAT_EQ(mesh.positions[0][0], -2.36702e-08f);
  EXPECT_FLOAT_EQ(mesh.positions[0][1], 1.5f);
}

TEST(ObjReader, ErrorsNameTheLine) {
  for (const char* bad : {"v 1 2\n", "v 0 0 0\nf 1 2 3\n", "v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 x 3\n",
                          "v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2\n"}) {
    try {
      parse_obj(bad, "bad.obj");
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find("bad.obj' line"), std::string::npos) << error.what();
    }
  }
}

TEST(ExrIo, NamedChannelsAndMetadataRoundTrip) {
  testing::ScratchDir dir("synth-io");
  LayeredImage image(5, 3, {"R", "G", "B", "albedo.R", "visibility.8", "depth.Z"});
  for (size_t k = 0; k < image.pixels.size(); ++k) image.pixels[k] = std::sin(0.37f * k) * 1e3f;
  image.set_metadata("facetool:light_sh", "0.1 0.2 0.30000000000000004");
  image.set_metadata("facetool:seed", "18446744073709551615");
  write_exr_atomically(dir.file("x.exr"), image);
  const LayeredImage back = read_exr(dir.file("x.exr"), "facetool:");
  ASSERT_EQ(back.width, 5);
  ASSERT_EQ(back.height, 3);
  for (const std::string& name : image.channel_names) {
    const int a = image.find_channel(name), b = back.find_channel(name);
    ASSERT_GE(b, 0) << name;
    for (size_t p = 0; p < image.plane_size(); ++p) EXPECT_EQ(back.plane(b)[p], image.plane(a)[p]);
  }
  ASSERT_NE(back.find_metadata("facetool:light_sh"), nullptr);
  EXPECT_EQ(*back.find_metadata("facetool:light_sh"), "0.1 0.2 0.30000000000000004");
  EXPECT_EQ(*back.find_metadata("facetool:seed"), "18446744073709551615");
  const LayeredImage header = read_exr_header(dir.file("x.exr"), "facetool:");
  EXPECT_TRUE(header.pixels.empty());
  EXPECT_EQ(header.metadata.size(), 2u);
  EXPECT_THROW(read_exr(dir.file("absent.exr")), Error);
}

TEST(ImageIo, PngRoundTripWithSrgbEncoding) {
  testing::ScratchDir dir("synth-png");
  RgbImage rgb;
  rgb.width = 4;
  rgb.height = 2;
  rgb.pixels = {0, 0.5f, 1, 0.2f, 0.04f, 0.9f, 1, 1, 1, 0, 0, 0, 0.5f, 0.5f, 0.5f, 0.1f, 0.3f, 0.7f,
                0.25f, 0.75f, 0.0f, 0.6f, 0.6f, 0.6f};
  write_png_atomically(dir.file("a.png"), rgb);
  const RgbImage back = read_rgb_image(dir.file("a.png"), true);
  ASSERT_EQ(back.pixels.size(), rgb.pixels.size());
  for (size_t k = 0; k < rgb.pixels.size(); ++k) EXPECT_NEAR(back.pixels[k], rgb.pixels[k], 0.01f);
}

}  // namespace
}  // namespace facetool
