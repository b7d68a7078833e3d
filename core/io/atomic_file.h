// Forwarding header: atomic writes moved to core/util/atomic_file.h (part of libfacetool_core, so
// that backend modules can use them); kept so that older includes still build.
#pragma once

#include "core/util/atomic_file.h"
