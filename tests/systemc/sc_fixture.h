// A fresh SystemC simulation context per test, so a test may elaborate and run its own top
// even when the whole binary runs in one process (SystemC 2.3 elaborates once per context).
#pragma once
#include <gtest/gtest.h>

#include <systemc>

namespace rtusim::testing {

class SystemCTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // The previous context is left alive: its modules may still refer to it.
    sc_core::sc_curr_simcontext = new sc_core::sc_simcontext;
    sc_core::sc_default_global_context = sc_core::sc_curr_simcontext;
  }
};

}  // namespace rtusim::testing
