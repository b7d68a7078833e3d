// A valid plugin that reuses good_loss's name "test_loss": the loader must refuse the second one.
#include "core/plugin/plugin_api.h"
#include "test_plugin_interface.h"

namespace {

class SecondLoss : public facetool::TestPluginInterface {
 public:
  void set_destroyed_flag(int*) override {}
  int answer() const override { return 7; }
};

}  // namespace

FACETOOL_DEFINE_PLUGIN(SecondLoss, FACETOOL_PLUGIN_LOSS, "test_loss", "9.9.9",
                       "a second plugin claiming the name test_loss")
