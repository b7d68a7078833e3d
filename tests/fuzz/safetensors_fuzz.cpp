// libFuzzer target: the safetensors parser must refuse any byte string cleanly, never crash.
#include <cstddef>
#include <cstdint>

#include "core/model/safetensors.h"
#include "core/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    facetool::SafeTensors st = facetool::SafeTensors::parse(data, size, "fuzz input");
    for (const auto& name : st.names())
      if (st.entry(name).dtype == "F32") st.floats(name);
  } catch (const facetool::Error&) {
  }
  return 0;
}
