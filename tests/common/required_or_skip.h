// Tests that need what a developer's machine may lack (olad, node and the npm
// senders, root for a private network namespace) skip there, saying what is
// missing. CI sets RELIGHT_REQUIRE_DMX_WIRE=1 (.ci/run installs all of it and
// runs as root): then the same condition fails the test, so a broken install
// cannot turn the end-to-end DMX tests into silent skips and a green run.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <sstream>

namespace relight::testing {

inline bool DmxWireRequired() {
  const char* v = std::getenv("RELIGHT_REQUIRE_DMX_WIRE");
  return v != nullptr && std::strcmp(v, "0") != 0 && *v != '\0';
}

}  // namespace relight::testing

// RELIGHT_SKIP_UNLESS_REQUIRED("olad not installed" << ...): skips, or fails when required.
#define RELIGHT_SKIP_UNLESS_REQUIRED(message)                                                  \
  do {                                                                                         \
    std::ostringstream relight_why_;                                                           \
    relight_why_ << message;                                                                   \
    if (::relight::testing::DmxWireRequired()) {                                               \
      GTEST_FAIL() << "RELIGHT_REQUIRE_DMX_WIRE is set, so this test may not skip: "           \
                   << relight_why_.str();                                                      \
    }                                                                                          \
    GTEST_SKIP() << relight_why_.str();                                                        \
  } while (0)
