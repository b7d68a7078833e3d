// Factory of the cpu backend: the plain C++ reference that defines every op's semantics.
#pragma once

#include <memory>

#include "core/backend/backend.h"

namespace facetool {

std::unique_ptr<Backend> make_cpu_backend();

}  // namespace facetool
