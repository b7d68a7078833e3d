// DatasetReader: batches hold the files' values with the eroded mask, each epoch covers every
// sample once in a seed-determined order.
#include <set>

#include "core/backend/registry.h"
#include "libs/data/dataset_reader.h"
#include "libs/synth/gbuffer.h"
#include "libs/synth/synth_runner.h"
#include "core/util/error.h"
#include "synth_test_support.h"

namespace facetool {
namespace {

class DatasetReaderTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    lights = new testing::ScratchDir("synth-dataset-lights");
    data = new testing::ScratchDir("synth-dataset");
    testing::write_text(lights->file("l.txt"), "1 1 1\n0.2 0.1 0\n0.4 0.4 0.4\n0 0.1 0.2\n0 0 0\n0 0 0\n0.1 0.1 0.1\n0 0 0\n0 0 0\n");
    SynthSettings settings;
    settings.camera.width = 24;
    settings.camera.height = 16;
    settings.direction_count = 100;
    FaceSource faces;
    faces.mesh = std::make_shared<const FaceMesh>(testing::make_sphere(16, 32));
    SampleGenerator generator(faces, load_light_sources({lights->path()}), BackgroundSource(),
                              make_reference_renderer(), settings);
    SynthRunOptions options;
    options.output_dir = data->path();
    options.count = 7;
    run_synth(generator, options);
  }
  static void TearDownTestSuite() {
    delete data;
    delete lights;
  }
  static testing::ScratchDir* lights;
  static testing::ScratchDir* data;
};
testing::ScratchDir* DatasetReaderTest::lights = nullptr;
testing::ScratchDir* DatasetReaderTest::data = nullptr;

TEST_F(DatasetReaderTest, BatchesHoldTheStoredValuesAndTheErodedMask) {
  DatasetReaderOptions options;
  options.directory = data->path();
  options.batch_size = 3;
  DatasetReader reader(get_backend("cpu"), options);
  EXPECT_EQ(reader.sample_count(), 7u);
  const SyntheticBatch batch = reader.next();
  EXPECT_EQ(batch.image.shape(), (Shape{3, 3, 16, 24}));
  EXPECT_EQ(batch.mask.shape(), (Shape{3, 1, 16, 24}));
  EXPECT_EQ(batch.visibility.shape(), (Shape{3, 9, 16, 24}));
  EXPECT_EQ(batch.light.shape(), (Shape{3, 27}));
  const std::vector<float> image = batch.image.to_host(), mask = batch.mask.to_host(),
                           visibility = batch.visibility.to_host(), light = batch.light.to_host();
  for (int b = 0; b < 3; ++b) {
    const SynthSample s = read_synth_sample(batch.files[b]);
    const size_t plane = s.plane();
    const std::vector<float> eroded = erode_mask(s.mask, s.width, s.height);
    for (size_t k = 0; k < 3 * plane; ++k) EXPECT_EQ(image[b * 3 * plane + k], s.image[k]);
    for (size_t k = 0; k < 9 * plane; ++k) EXPECT_EQ(visibility[b * 9 * plane + k], s.visibility[k]);
    for (size_t k = 0; k < plane; ++k) EXPECT_EQ(mask[b * plane + k], eroded[k]);
    for (int k = 0; k < 27; ++k) EXPECT_FLOAT_EQ(light[b * 27 + k], static_cast<float>(s.light[k]));
    int full = 0, inner = 0;
    for (size_t k = 0; k < plane; ++k) {
      full += s.mask[k] > 0.5f;
      inner += eroded[k] > 0.5f;
    }
    EXPECT_GT(inner, 0);
    EXPECT_LT(inner, full);
  }
}

TEST_F(DatasetReaderTest, EachEpochVisitsEverySampleOnceInASeededOrder) {
  DatasetReaderOptions options;
  options.directory = data->path();
  options.batch_size = 2;  // 7 samples: 3 batches per epoch, one sample left out each epoch
  options.seed = 4;
  DatasetReader first(get_backend("cpu"), options), second(get_backend("cpu"), options);
  std::vector<std::string> order_a, order_b;
  for (int k = 0; k < 6; ++k) {
    const SyntheticBatch a = first.next(), b = second.next();
    EXPECT_EQ(a.epoch, k / 3);
    order_a.insert(order_a.end(), a.files.begin(), a.files.end());
    order_b.insert(order_b.end(), b.files.begin(), b.files.end());
  }
  EXPECT_EQ(order_a, order_b);
  EXPECT_EQ(std::set<std::string>(order_a.begin(), order_a.begin() + 6).size(), 6u);
  EXPECT_NE(std::vector<std::string>(order_a.begin(), order_a.begin() + 6),
            std::vector<std::string>(order_a.begin() + 6, order_a.end()));
}

// Too few samples for one batch: the message says which part of the split ran short (7
// samples, every 3rd index held out: indices 0, 3 and 6 validate, so 3 rows, not 4).
TEST_F(DatasetReaderTest, TooFewSamplesNamesThePartOfTheSplit) {
  DatasetReaderOptions options;
  options.directory = data->path();
  options.batch_size = 4;
  options.holdout_every = 3;
  options.part = DatasetReaderOptions::Part::kValidation;
  try {
    DatasetReader reader(get_backend("cpu"), options);
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("holds 3 samples in its validation part (the sample indices divisible by 3), "
                           "fewer than one batch of 4"), std::string::npos) << message;
    EXPECT_NE(message.find("validation.holdout_every"), std::string::npos) << message;
  }
  options.part = DatasetReaderOptions::Part::kAll;
  options.batch_size = 8;
  try {
    DatasetReader reader(get_backend("cpu"), options);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("holds 7 samples, fewer than one batch of 8; add samples"),
              std::string::npos) << e.what();
  }
}

TEST(DatasetReaderErrors, EmptyOrMissingFolder) {
  testing::ScratchDir empty("synth-dataset-empty");
  DatasetReaderOptions options;
  options.directory = empty.path();
  EXPECT_THROW(DatasetReader(get_backend("cpu"), options), Error);
  options.directory = empty.file("absent");
  EXPECT_THROW(DatasetReader(get_backend("cpu"), options), Error);
}

}  // namespace
}  // namespace facetool
