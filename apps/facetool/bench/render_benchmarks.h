// Renderer benchmarks: forward and backward of a renderer plugin at a training batch's size.
#pragma once

#include <ostream>

#include "core/plugin/renderer_plugin.h"

namespace facetool {

// Times forward (image + shading) and backward (gradients to all four inputs) of `renderer` on
// `batch` random images of size x size with every pixel inside the mask; prints medians of
// `repeats` runs after a warm-up.
void run_render_benchmarks(RendererPlugin& renderer, Backend& backend, int batch, int size,
                           int repeats, std::ostream& out);

}  // namespace facetool
