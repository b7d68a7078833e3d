// The interface the test plugins implement, shared by the plugins and the loader tests.
#pragma once

#include "core/plugin/plugin.h"

namespace facetool {

class TestPluginInterface : public Plugin {
 public:
  // The destructor sets *flag to 1, so a test can see that the plugin's destroy ran.
  virtual void set_destroyed_flag(int* flag) = 0;
  virtual int answer() const = 0;
};

}  // namespace facetool
