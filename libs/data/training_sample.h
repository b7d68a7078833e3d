// TrainingSample: the planes a training batch needs, read from a synthetic or a real sample EXR.
#pragma once

#include <string>
#include <vector>

#include "libs/io/layered_image.h"
#include "libs/io/sample_files.h"

namespace facetool {

// Planar [channels][height * width]. Real samples without labels have `labelled` false and
// albedo, normal, visibility and light filled with zeros. `prior` holds the network's input
// prior when one was asked for (channels prior.X/Y/Z for "fit_normal"), else nothing.
struct TrainingSample {
  int width = 0, height = 0;
  std::vector<float> image, albedo, normal, mask, visibility, light;  // light: 27
  std::vector<float> prior;
  // facetool:landmarks: 68 (x, y) in the sample's pixels (synth: the landmark vertices
  // projected; prepare-real: the detector's points mapped into the crop); empty when absent.
  std::vector<float> landmarks;
  bool labelled = false;
  bool real = false;
};

// Reads a synthetic sample (facetool synth) or a real one (generator facetool-real-1: channels
// R G B mask, and when pseudo-labelled albedo.R/G/B normal.X/Y/Z visibility.0..8 plus the
// facetool:light_sh attribute). With `need_labels`, a real sample without labels is an error
// naming the file and saying to run `facetool pseudo-label`. With an `input_prior`
// (NetworkConfig::input_prior) the sample must carry its channels (prior.X/Y/Z for
// "fit_normal", written by `facetool pseudo-label --from fit`); a sample without is an error
// naming the file and the command.
TrainingSample read_training_sample(const std::string& path, bool need_labels,
                                    const std::string& input_prior = "");

// A sample's facetool:landmarks as 136 finite numbers (68 (x, y) pairs), empty when it has no
// such attribute; a malformed one is an error naming `path`. (The one reader of the attribute:
// training samples, pseudo-label's inputs, the fit's targets.)
std::vector<double> sample_landmarks(const LayeredImage& sample, const std::string& path);

// TrainingSample::landmarks from the file's header alone (empty: the sample has none).
std::vector<float> read_training_sample_landmarks(const std::string& path);

// Width and height from the file's header.
void read_training_sample_size(const std::string& path, int& width, int& height);

// The framing the sample was made at: its facetool:framing attribute (synth --framing,
// prepare-real --framing; libs/image/crop_framing.h), or "v1" when it has none.
std::string read_training_sample_framing(const std::string& path);

}  // namespace facetool
