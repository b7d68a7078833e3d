// Missing or broken inputs give facetool::Error messages that name the file and what to do.
#include <filesystem>

#include "libs/synth/face_model.h"
#include "libs/synth/light_source.h"
#include "core/util/error.h"
#include "synth_test_support.h"

namespace facetool {
namespace {
namespace fs = std::filesystem;

// Runs `action`, expecting facetool::Error whose message contains every one of `parts`.
template <typename Action>
void expect_error(Action action, std::initializer_list<std::string> parts) {
  try {
    action();
    ADD_FAILURE() << "no error thrown";
  } catch (const Error& error) {
    const std::string message = error.what();
    for (const std::string& part : parts)
      EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
  }
}

const char kCube[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

TEST(SynthErrors, MissingFaceModelSaysWhereToGetIt) {
  testing::ScratchDir dir("synth-errors-model");
  expect_error([&] { FaceModel::load(dir.file("nowhere")); },
               {"nowhere", "does not exist", "ICT-FaceKit", "--face-model"});
  expect_error([&] { FaceModel::load(dir.path()); },
               {"generic_neutral_mesh.obj", "github.com/ICT-VGL/ICT-FaceKit"});
}

TEST(SynthErrors, BrokenFaceModelFilesAreNamed) {
  testing::ScratchDir dir("synth-errors-broken");
  testing::write_text(dir.file("generic_neutral_mesh.obj"), "v 0 0 0\nv 1 0 zero\n");
  expect_error([&] { FaceModel::load(dir.path()); },
               {"generic_neutral_mesh.obj", "line 2", "expected a number"});
  testing::write_text(dir.file("generic_neutral_mesh.obj"), kCube);
  testing::write_text(dir.file("identity000.obj"), "v 0 0 0\nv 1 0 0\n");
  expect_error([&] { FaceModel::load(dir.path()); },
               {"identity000.obj", "2 vertices", "neutral mesh has 4"});
  testing::write_text(dir.file("identity000.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n");
  testing::write_text(dir.file("jawOpen.obj"), "v 0 0 0\nf 1 2 3\n");
  expect_error([&] { FaceModel::load(dir.path()); }, {"jawOpen.obj", "vertex index 2"});
  fs::remove(dir.file("jawOpen.obj"));
  // Without an expression (or identity) shape the fit cannot run: named, not a Ceres abort.
  expect_error([&] { FaceModel::load(dir.path()); }, {"0 expression shape files", "identityNNN.obj"});
  testing::write_text(dir.file("jawOpen.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n");
  // A NaN vertex in the neutral mesh or a shape, and a landmark list that is not numbers.
  testing::write_text(dir.file("smile.obj"), "v 0 0 0\nv 1 nan 0\nv 1 1 0\nv 0 1 0\n");
  expect_error([&] { FaceModel::load(dir.path()); }, {"smile.obj", "vertex 2", "not finite"});
  fs::remove(dir.file("smile.obj"));
  testing::write_text(dir.file("vertex_indices.json"), "{\"idx_to_landmark_verts\": [1, 2, x3]}");
  expect_error([&] { FaceModel::load(dir.path()); }, {"vertex_indices.json", "item 2", "x3"});
  testing::write_text(dir.file("vertex_indices.json"), "{\"idx_to_landmark_verts\": [1, 99999999999999]}");
  expect_error([&] { FaceModel::load(dir.path()); }, {"vertex_indices.json", "item 1"});
  fs::remove(dir.file("vertex_indices.json"));
  // A shape stored the upstream way (full OBJ with texture coordinates and faces) loads the
  // same as a vertex-only one.
  testing::write_text(dir.file("identity001.obj"),
                      "v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                      "f 1/1 2/2 3/3 4/4\n");
  const FaceModel model = FaceModel::load(dir.path());
  EXPECT_EQ(model.identity_count(), 2);
  EXPECT_EQ(model.neutral().triangles.size(), 2u);
  ShapeWeights weights;
  weights.identity = {0.0f, 0.5f};
  weights.expression = {0.0f};
  const FaceMesh moved = model.build(weights);
  for (const Vec3f& p : moved.positions) EXPECT_FLOAT_EQ(p.z, 0.5f);
}

TEST(SynthErrors, BrokenLightFilesAreNamed) {
  testing::ScratchDir dir("synth-errors-lights");
  expect_error([&] { load_light_sources({dir.file("missing")}); }, {"missing", "--lights"});
  expect_error([&] { load_light_sources({dir.path()}); }, {"no light files", "blender-data"});
  testing::write_text(dir.file("short.txt"), "1 2 3\n4 5\n");
  expect_error([&] { load_light_sources({dir.path()}); }, {"short.txt", "5 numbers", "27"});
  fs::remove(dir.file("short.txt"));
  testing::write_text(dir.file("word.txt"), "1 2 three\n");
  expect_error([&] { load_light_sources({dir.path()}); }, {"word.txt", "three"});
  fs::remove(dir.file("word.txt"));
  testing::write_text(dir.file("broken.hdr"), "#?RADIANCE\nthis is not a picture");
  expect_error([&] { load_light_sources({dir.path()}); }, {"broken.hdr"});
  fs::remove(dir.file("broken.hdr"));
  std::string black;
  for (int k = 0; k < 27; ++k) black += "0 ";
  testing::write_text(dir.file("black.txt"), black);
  expect_error([&] { load_light_sources({dir.path()}); }, {"black.txt", "black"});
}

// A light folder's licence and readme notes are not lights (blender-data ships license.txt);
// a note passed explicitly as a file is still read, and fails as a light would.
TEST(SynthErrors, LightFoldersSkipLicenceAndReadmeNotes) {
  testing::ScratchDir dir("synth-light-notes");
  std::string grey;
  for (int k = 0; k < 9; ++k) grey += k == 0 ? "1 1 1\n" : "0 0 0\n";
  testing::write_text(dir.file("grey.txt"), grey);
  testing::write_text(dir.file("license.txt"), "All files are CC0.\n");
  testing::write_text(dir.file("README.txt"), "Lights for testing.\n");
  const std::vector<LightSource> sources = load_light_sources({dir.path()});
  ASSERT_EQ(sources.size(), 1u);
  EXPECT_EQ(sources[0].name, "grey.txt");
  expect_error([&] { load_light_sources({dir.file("license.txt")}); }, {"license.txt", "All"});
}

TEST(SynthErrors, UserMeshWithoutFaces) {
  testing::ScratchDir dir("synth-errors-mesh");
  testing::write_text(dir.file("points.obj"), "v 0 0 0\nv 1 0 0\n");
  expect_error([&] { load_user_mesh(dir.file("points.obj")); }, {"points.obj", "no faces"});
  expect_error([&] { load_user_mesh(dir.file("absent.obj")); }, {"absent.obj", "does not exist"});
}

}  // namespace
}  // namespace facetool
