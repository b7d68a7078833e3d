// A well-formed loss plugin for the loader tests; its object answers 42.
#include "core/plugin/plugin_api.h"
#include "test_plugin_interface.h"

namespace {

class GoodLoss : public facetool::TestPluginInterface {
 public:
  ~GoodLoss() override {
    if (destroyed_flag_) *destroyed_flag_ = 1;
  }
  void set_destroyed_flag(int* flag) override { destroyed_flag_ = flag; }
  int answer() const override { return 42; }

 private:
  int* destroyed_flag_ = nullptr;
};

}  // namespace

FACETOOL_DEFINE_PLUGIN(GoodLoss, FACETOOL_PLUGIN_LOSS, "test_loss", "1.2.3",
                       "a loss plugin used by the plugin loader tests")
