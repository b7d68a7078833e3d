// The decomposer's batch loop and the concatenation of its results.
#include "libs/inference/batched_decomposition.h"

#include <algorithm>

#include "core/util/error.h"

namespace facetool {

void decompose_in_batches(Decomposer& decomposer, Backend& backend, size_t count, int batch,
                          const std::function<void(size_t k, std::vector<float>& inputs)>& load,
                          const std::function<void(size_t first, const Decomposition& d,
                                                   const std::vector<float>& inputs)>& use,
                          const std::function<bool(size_t k, std::vector<float>& landmarks)>& landmarks_of) {
  check(batch >= 1, "the batch size must be at least 1 (it is ", batch, ")");
  std::vector<float> inputs, landmarks;
  for (size_t first = 0; first < count; first += static_cast<size_t>(batch)) {
    const size_t n = std::min(count - first, static_cast<size_t>(batch));
    inputs.clear();
    landmarks.clear();
    bool all_landmarks = static_cast<bool>(landmarks_of);
    for (size_t k = first; k < first + n; ++k) {
      load(k, inputs);
      if (all_landmarks) all_landmarks = landmarks_of(k, landmarks);
    }
    const Decomposition d = decomposer.run(backend, inputs, static_cast<int>(n), all_landmarks ? &landmarks : nullptr);
    use(first, d, inputs);
  }
}

void append_decomposition(Decomposition& a, const Decomposition& b) {
  check(a.count == 0 || a.size == b.size, "cannot join decompositions of ", a.size, " and ", b.size, " pixel crops");
  a.size = b.size;
  a.count += b.count;
  auto append = [](std::vector<float>& to, const std::vector<float>& from) {
    to.insert(to.end(), from.begin(), from.end());
  };
  append(a.albedo, b.albedo);
  append(a.normal, b.normal);
  append(a.visibility, b.visibility);
  append(a.light, b.light);
  append(a.shading, b.shading);
  append(a.reconstruction, b.reconstruction);
  a.light_solve.insert(a.light_solve.end(), b.light_solve.begin(), b.light_solve.end());
}

Decomposition decomposition_images(const Decomposition& d, int first, int count) {
  check(first >= 0 && count >= 0 && first + count <= d.count, "images ", first, " to ", first + count - 1,
        " of a decomposition of ", d.count);
  Decomposition out;
  out.count = count;
  out.size = d.size;
  auto take = [&](const std::vector<float>& from, size_t per_image) {
    return std::vector<float>(from.begin() + first * per_image, from.begin() + (first + count) * per_image);
  };
  const size_t plane = static_cast<size_t>(d.size) * d.size;
  out.albedo = take(d.albedo, 3 * plane);
  out.normal = take(d.normal, 3 * plane);
  out.visibility = take(d.visibility, 9 * plane);
  out.light = take(d.light, 27);
  out.shading = take(d.shading, 3 * plane);
  out.reconstruction = take(d.reconstruction, 3 * plane);
  if (d.light_solve.size() == static_cast<size_t>(d.count))
    out.light_solve.assign(d.light_solve.begin() + first, d.light_solve.begin() + first + count);
  return out;
}

Decomposition decompose_all(Decomposer& decomposer, Backend& backend, const std::vector<float>& crops,
                            int count, int size, int batch, const std::vector<float>* landmarks) {
  const int channels = 3 + input_prior_channels(decomposer.network().config().input_prior);
  const size_t image = static_cast<size_t>(channels) * size * size;
  check(count >= 0 && crops.size() == static_cast<size_t>(count) * image, "decompose_all: ", crops.size(),
        " values are not ", count, " crops of ", channels, "x", size, "x", size);
  constexpr size_t kPoints = 2 * LandmarkNormals::kLandmarks;
  check(!landmarks || landmarks->size() == static_cast<size_t>(count) * kPoints, "decompose_all: ",
        landmarks ? landmarks->size() : 0, " landmark coordinates for ", count, " crops");
  Decomposition all;
  decompose_in_batches(
      decomposer, backend, static_cast<size_t>(count), batch,
      [&](size_t k, std::vector<float>& inputs) {
        inputs.insert(inputs.end(), crops.begin() + k * image, crops.begin() + (k + 1) * image);
      },
      [&](size_t, const Decomposition& d, const std::vector<float>&) { append_decomposition(all, d); },
      [&](size_t k, std::vector<float>& points) {
        if (!landmarks) return false;
        points.insert(points.end(), landmarks->begin() + k * kPoints, landmarks->begin() + (k + 1) * kPoints);
        return true;
      });
  return all;
}

}  // namespace facetool
