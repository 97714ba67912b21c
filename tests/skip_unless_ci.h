// A test whose input (a shared scene, a tool) is missing skips on a developer's machine, but
// fails in CI (environment CI set, and not "false" or "0"), where every input must be present.
#pragma once
#include <cstdlib>
#include <cstring>

#include <gtest/gtest.h>

namespace rtusim::testing {

inline bool in_ci() {
  const char* ci = std::getenv("CI");
  return ci && *ci && std::strcmp(ci, "false") != 0 && std::strcmp(ci, "0") != 0;
}

}  // namespace rtusim::testing

#define RTUSIM_SKIP_UNLESS_CI(why)                                             \
  do {                                                                         \
    if (::rtusim::testing::in_ci()) FAIL() << why << " (in CI this is a failure)"; \
    GTEST_SKIP() << why;                                                       \
  } while (0)
