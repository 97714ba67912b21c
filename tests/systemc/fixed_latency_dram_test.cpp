// The fixed-latency DRAM model (dram.backend = "fixed"): latency plus bus time, the bus shared
// in arrival order (equal arrivals by address), channels independent, bytes counted.
#include <gtest/gtest.h>

#include <vector>

#include "mem/dram/fixed_latency_dram.h"
#include "util/stats.h"

namespace rtusim {
namespace {

DramParams fixed_dram(uint32_t channels = 1) {
  DramParams p;
  p.backend = "fixed";
  p.channels = channels;
  p.row_bytes = 1024;  // channel = (addr / 1024) % channels
  return p;
}

TEST(FixedLatencyDramTest, IsolatedRequestTakesLatencyPlusBursts) {
  const DramParams p = fixed_dram();
  FixedLatencyDram d(p);
  d.enqueue({1, 0x40, 64, 5000, Stream::kNode});
  EXPECT_EQ(d.next_decision_ps(), 5000u);
  std::vector<DramCompletion> out;
  d.advance(4999, out);
  EXPECT_TRUE(out.empty());
  d.advance(5000, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].done_ps, 5000 + p.latency_ps() + p.burst_ps());
  EXPECT_EQ(d.next_decision_ps(), DramBackend::kNever);
  // Two bursts for 128 bytes.
  d.enqueue({2, 0x80, 128, 1'000'000, Stream::kTriangle});
  out.clear();
  d.advance(1'000'000, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].done_ps, 1'000'000 + p.latency_ps() + 2 * p.burst_ps());
  Stats s;
  d.write_stats(s, "dram");
  EXPECT_EQ(s.at("dram.requests").get<uint64_t>(), 2u);
  EXPECT_EQ(s.at("dram.bytes.nodes").get<uint64_t>(), 64u);
  EXPECT_EQ(s.at("dram.bytes.triangles").get<uint64_t>(), 128u);
  EXPECT_EQ(s.at("dram.bytes.total").get<uint64_t>(), 192u);
}

TEST(FixedLatencyDramTest, BusSharedInArrivalThenAddressOrder) {
  const DramParams p = fixed_dram();
  FixedLatencyDram d(p);
  // Enqueued out of address order at the same time: served by address.
  d.enqueue({1, 0x100, 64, 0, Stream::kNode});
  d.enqueue({2, 0x000, 64, 0, Stream::kNode});
  std::vector<DramCompletion> out;
  d.advance(0, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].id, 2u);
  EXPECT_EQ(out[0].done_ps, p.latency_ps() + p.burst_ps());
  EXPECT_EQ(out[1].id, 1u);
  EXPECT_EQ(out[1].done_ps, p.latency_ps() + 2 * p.burst_ps());  // waits for the bus
}

TEST(FixedLatencyDramTest, ChannelsHaveTheirOwnBus) {
  const DramParams p = fixed_dram(2);
  FixedLatencyDram d(p);
  d.enqueue({1, 0x000, 64, 0, Stream::kNode});  // channel 0
  d.enqueue({2, 0x400, 64, 0, Stream::kNode});  // channel 1
  std::vector<DramCompletion> out;
  d.advance(0, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].done_ps, out[1].done_ps);
}

}  // namespace
}  // namespace rtusim
