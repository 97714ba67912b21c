// The unit's intersection pipeline (isect.lanes, isect.interval_cycles, isect.latency_cycles):
// each test takes the lane that is free first, from the cycle its data is there; a lane takes a
// new test every interval, and a test's result is there latency cycles after it started. Shared
// by the cycle tier's unit and the timed interleaved functional mode.
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

#include "model/unit_params.h"

namespace rtusim {

class IsectLanes {
 public:
  explicit IsectLanes(const UnitParams& p)
      : free_(p.isect_lanes, 0), interval_cycles_(p.isect_interval_cycles),
        latency_cycles_(p.isect_latency_cycles) {}

  // Books `tests` tests whose data is there at cycle t; returns the cycle the last result is in
  // (t when there are none).
  uint64_t book(size_t tests, uint64_t t) {
    uint64_t end = t;
    for (size_t i = 0; i < tests; ++i) {
      auto lane = std::min_element(free_.begin(), free_.end());
      const uint64_t start = std::max(t, *lane);
      *lane = start + interval_cycles_;
      end = std::max(end, start + latency_cycles_);
    }
    return end;
  }

 private:
  std::vector<uint64_t> free_;  // per lane: the next cycle it takes a test
  uint32_t interval_cycles_;
  uint32_t latency_cycles_;
};

}  // namespace rtusim
