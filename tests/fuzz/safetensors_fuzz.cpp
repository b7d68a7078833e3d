// libFuzzer target: the safetensors parser must refuse any byte string cleanly, never crash, and
// what it accepts must be self-consistent (each F32 tensor holds as many values as its shape).
#include <cstddef>
#include <cstdint>

#include "libs/model/safetensors.h"
#include "core/util/error.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    facetool::SafeTensors st = facetool::SafeTensors::parse(data, size, "fuzz input");
    for (const auto& name : st.names()) {
      const facetool::SafeTensors::Entry& entry = st.entry(name);
      facetool::fuzz::require(entry.begin <= entry.end && entry.end <= size,
                              "accepted tensor bytes lie outside the input");
      if (entry.dtype != "F32") continue;
      uint64_t count = 1;
      for (int64_t d : entry.shape) count *= static_cast<uint64_t>(d);
      facetool::fuzz::require(st.floats(name).size() == count,
                              "an accepted F32 tensor's value count differs from its shape");
    }
  } catch (const facetool::Error&) {
  }
  return 0;
}
