// The one batch loop of the decomposer: a list of crops run `batch` at a time (infer, relight,
// pseudo-label, eval, the photo pipeline).
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "libs/inference/decomposer.h"

namespace facetool {

// Runs the decomposer over `count` inputs in batches of `batch`. For each batch, load(k, inputs)
// appends input k's planar linear RGB crop [3][S][S] (and the network's input prior after it,
// when it takes one: Decomposer::run) to `inputs` for k = first .. first + n - 1;
// then use(first, d, inputs) gets the batch's results (d's image i is input first + i) and the
// batch's inputs. `landmarks_of` (optional) appends input k's 68 landmarks ((x, y) in crop
// pixels) to its vector and says whether it has them; a batch whose inputs all have them runs
// with them (Decomposer::run: the landmark normal head). Throws facetool::Error when batch < 1.
void decompose_in_batches(Decomposer& decomposer, Backend& backend, size_t count, int batch,
                          const std::function<void(size_t k, std::vector<float>& inputs)>& load,
                          const std::function<void(size_t first, const Decomposition& d,
                                                   const std::vector<float>& inputs)>& use,
                          const std::function<bool(size_t k, std::vector<float>& landmarks)>& landmarks_of = {});

// Runs the decomposer over `count` planar crops [count][3+P][size][size] (P: the network's input
// prior channels, Decomposer::run) in batches of `batch` and concatenates the results;
// `landmarks` (optional): the crops' landmarks [count][68][2], crop pixels.
Decomposition decompose_all(Decomposer& decomposer, Backend& backend, const std::vector<float>& crops,
                            int count, int size, int batch, const std::vector<float>* landmarks = nullptr);

// Appends b's images to a (equal sizes; a may be empty).
void append_decomposition(Decomposition& a, const Decomposition& b);

// Images first .. first + count - 1 of d (facetool::Error when they are not all in d).
Decomposition decomposition_images(const Decomposition& d, int first, int count);

}  // namespace facetool
