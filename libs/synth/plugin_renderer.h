// A ComponentRenderer backed by a renderer plugin (e.g. sh_renderer), so generated images come
// from exactly the code the network's rendering layer runs.
#pragma once

#include <memory>

#include "libs/synth/component_renderer.h"

namespace facetool {

class Backend;
class RendererPlugin;

// Calls plugin->forward on tensors of `backend` (pixels as a 1 x n image). Calls are serialised
// with a mutex: plugins need not be thread-safe.
std::unique_ptr<ComponentRenderer> make_plugin_renderer(std::shared_ptr<RendererPlugin> plugin,
                                                        Backend& backend);

}  // namespace facetool
