// error_text: the message of the facetool::Error a piece of test code throws.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "core/util/error.h"

namespace facetool::testing {

// The message of the facetool::Error `action` throws; "" when it throws nothing (compare with ""
// to assert that), and a test failure when it throws anything else.
template <typename Action>
std::string error_text(Action action) {
  try {
    action();
  } catch (const Error& e) {
    return e.what();
  } catch (...) {
    ADD_FAILURE() << "expected a facetool::Error, got another exception";
    return "(not a facetool::Error)";
  }
  return "";
}

}  // namespace facetool::testing
