// Shared setup of the renderer tests: the loaded plugin, random scenes, a host-side render loss.
#pragma once

#include <string>
#include <vector>

#include "core/backend/backend.h"
#include "core/plugin/renderer_plugin.h"
#include "core/sh/sh_types.h"

namespace facetool::testing {

// The sh_renderer plugin loaded through PluginLoader::load_file from the build's path.
RendererPlugin& sh_renderer();

// Host-side scene: N images of H x W pixels in the tensor layouts of RenderInputs.
struct HostScene {
  int64_t n = 0, h = 0, w = 0;
  std::vector<float> albedo, normal, visibility, light, mask;  // mask empty = none
};

// Random albedo in [0.1, 1), normals of length in [0.5, 2), visibility of random spherical-cap
// occluders projected with 872 Fibonacci samples, lights with a positive constant term.
HostScene random_scene(int64_t n, int64_t h, int64_t w, unsigned seed);
RenderInputs upload(Backend& backend, const HostScene& scene);

// Visibility coefficients of one pixel / normal of one pixel / light of one image.
sh::ShCoeffs pixel_visibility(const HostScene& s, int64_t n, int64_t p);
sh::Vec3 pixel_normal(const HostScene& s, int64_t n, int64_t p);
sh::ShCoeffs image_light(const HostScene& s, int64_t n, int channel);

}  // namespace facetool::testing
