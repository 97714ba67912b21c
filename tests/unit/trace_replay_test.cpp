// replay_trace's filter of repeated lines: the same addresses kept, in order, and the same last
// line, as a plain one-at-a-time filter, for chunks of every length around the 8-wide step.
#include "app/trace_replay.h"

#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace rtusim {
namespace {

TEST(TraceReplayTest, DropRepeatedLinesKeepsEachLineChange) {
  std::mt19937_64 rng(3);
  uint64_t last = ~uint64_t{0}, want_last = last;
  for (int chunk = 0; chunk < 5000; ++chunk) {
    std::vector<uint64_t> addrs(rng() % 70);
    // Few lines, so repeats are frequent and runs cross the 8-address steps and chunk ends.
    for (uint64_t& a : addrs) a = (rng() % 4) * 64 + rng() % 64 + (rng() % 8 == 0 ? 4096 : 0);
    std::vector<uint64_t> want;
    for (const uint64_t a : addrs) {
      if (a >> 6 != want_last) want.push_back(a);
      want_last = a >> 6;
    }
    const size_t kept = drop_repeated_lines(addrs, 6, last);
    ASSERT_EQ(kept, want.size()) << "chunk " << chunk;
    ASSERT_TRUE(std::equal(want.begin(), want.end(), addrs.begin())) << "chunk " << chunk;
    ASSERT_EQ(last, want_last) << "chunk " << chunk;
  }
}

}  // namespace
}  // namespace rtusim
