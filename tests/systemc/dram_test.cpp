// DRAM timing model: row hit / miss / conflict latencies from the params, FR-FCFS order, the
// address mapping, and the same through the TLM module.
#include <gtest/gtest.h>


#include <vector>

#include "mem/dram/dram.h"
#include "mem/dram/fr_fcfs_dram.h"
#include "sc_fixture.h"
#include "tlm_test_modules.h"
#include "util/error.h"
#include "util/stats.h"

namespace rtusim {
namespace {

// One channel, 4 banks, 1 KB rows: bank = (addr / 1024) % 4, row = addr / 4096.
DramParams small_dram() {
  DramParams p;
  p.banks = 4;
  p.row_bytes = 1024;
  return p;
}
constexpr uint64_t kRow0Bank0 = 0x0000, kRow1Bank0 = 0x1000, kRow0Bank1 = 0x0400;

uint64_t latency_of(FrFcfsDram& d, uint64_t addr, uint64_t at_ps) {
  d.enqueue({7, addr, 64, at_ps, Stream::kNode});
  EXPECT_EQ(d.next_decision_ps(), at_ps);  // an idle bank starts at once
  std::vector<DramCompletion> out;
  d.advance(at_ps, out);
  EXPECT_EQ(out.size(), 1u);
  return out.empty() ? 0 : out[0].done_ps - at_ps;
}

TEST(DramTest, PresetTimingsInPicoseconds) {
  const DramParams p = dram_preset("DDR4-2400");
  EXPECT_EQ(p.tRCD_ps(), 14160u);
  EXPECT_EQ(p.tRP_ps(), 14160u);
  EXPECT_EQ(p.tCL_ps(), 14160u);
  EXPECT_EQ(p.burst_ps(), 3333u);  // BL8 at 2400 MT/s
  EXPECT_EQ(p.burst_bytes(), 64u);
  EXPECT_EQ(dram_preset("DDR4-3200").burst_ps(), 2500u);
  EXPECT_THROW(dram_preset("DDR5-9000"), InputError);
}

TEST(DramTest, RowMissHitConflictLatencies) {
  const DramParams p = small_dram();
  const uint64_t rcd = p.tRCD_ps(), rp = p.tRP_ps(), cl = p.tCL_ps(), burst = p.burst_ps();
  FrFcfsDram d(p);
  // Far apart, so each request finds the bank and the bus idle.
  EXPECT_EQ(latency_of(d, kRow0Bank0, 0), rcd + cl + burst);                 // closed bank
  EXPECT_EQ(latency_of(d, kRow0Bank0 + 64, 1'000'000), cl + burst);          // same row
  EXPECT_EQ(latency_of(d, kRow1Bank0, 2'000'000), rp + rcd + cl + burst);    // other row
  EXPECT_EQ(latency_of(d, kRow0Bank1, 3'000'000), rcd + cl + burst);         // other bank
  EXPECT_EQ(d.row_hits(), 1u);
  EXPECT_EQ(d.row_misses(), 2u);
  EXPECT_EQ(d.row_conflicts(), 1u);
  Stats s;
  d.write_stats(s, "dram");
  EXPECT_DOUBLE_EQ(s.at("dram.row_hit_rate").get<double>(), 0.25);
  EXPECT_EQ(s.at("dram.bytes.nodes").get<uint64_t>(), 4u * 64);
}

TEST(DramTest, FrFcfsServesAYoungerRowHitFirst) {
  const DramParams p = small_dram();
  const uint64_t rcd = p.tRCD_ps(), rp = p.tRP_ps(), cl = p.tCL_ps(), burst = p.burst_ps();
  FrFcfsDram d(p);
  std::vector<DramCompletion> out;
  d.enqueue({1, kRow0Bank0, 64, 0, Stream::kNode});  // opens row 0 of bank 0
  d.advance(0, out);
  ASSERT_EQ(out.size(), 1u);
  // While bank 0 is busy: an older request to another row, then a younger one to the open row.
  d.enqueue({2, kRow1Bank0, 64, 1000, Stream::kNode});
  d.enqueue({3, kRow0Bank0 + 128, 64, 2000, Stream::kNode});
  const uint64_t ready = rcd + burst;  // bank 0 takes its next column command
  EXPECT_EQ(d.next_decision_ps(), ready);
  d.advance(ready - 1, out);
  EXPECT_EQ(out.size(), 1u);
  d.advance(ready, out);
  ASSERT_EQ(out.size(), 2u);  // the row hit; the conflict waits for the bank again
  EXPECT_EQ(out[1].id, 3u);
  const uint64_t bus_free = rcd + cl + burst;  // request 1's data
  EXPECT_EQ(out[1].done_ps, std::max(ready + cl, bus_free) + burst);
  EXPECT_EQ(d.next_decision_ps(), ready + burst);
  d.advance(ready + burst, out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[2].id, 2u);
  EXPECT_EQ(out[2].done_ps, ready + burst + rp + rcd + cl + burst);
  EXPECT_EQ(d.next_decision_ps(), DramBackend::kNever);
}

TEST(DramTest, EqualArrivalsGoByAddressNotByEnqueueOrder) {
  // Two row hits to the same open row arriving at the same time, enqueued in either order:
  // the lower address is served first, so the order initiators call in does not matter.
  for (const bool lower_first : {true, false}) {
    FrFcfsDram d(small_dram());
    std::vector<DramCompletion> out;
    d.enqueue({1, kRow0Bank0, 64, 0, Stream::kNode});  // opens row 0 of bank 0
    d.advance(0, out);
    const uint64_t lo = kRow0Bank0 + 128, hi = kRow0Bank0 + 256;
    d.enqueue({lower_first ? 2u : 3u, lower_first ? lo : hi, 64, 1000, Stream::kNode});
    d.enqueue({lower_first ? 3u : 2u, lower_first ? hi : lo, 64, 1000, Stream::kNode});
    while (out.size() < 3) d.advance(d.next_decision_ps(), out);
    EXPECT_EQ(out[1].id, 2u) << "lower_first " << lower_first;  // id 2 is the lower address
    EXPECT_EQ(out[2].id, 3u);
    EXPECT_LT(out[1].done_ps, out[2].done_ps);
  }
}

TEST(DramTest, BanksOverlapAndShareTheBus) {
  const DramParams p = small_dram();
  const uint64_t rcd = p.tRCD_ps(), cl = p.tCL_ps(), burst = p.burst_ps();
  FrFcfsDram d(p);
  std::vector<DramCompletion> out;
  d.enqueue({1, kRow0Bank0, 64, 0, Stream::kNode});
  d.enqueue({2, kRow0Bank1, 128, 0, Stream::kList});  // two bursts
  d.advance(0, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].done_ps, rcd + cl + burst);
  EXPECT_EQ(out[1].done_ps, rcd + cl + 3 * burst);  // waits for the bus, then two bursts
  EXPECT_EQ(d.bytes(Stream::kList), 128u);
}

TEST(DramTest, AddressMappingRowBankChannelColumn) {
  DramParams p = small_dram();
  p.channels = 2;
  FrFcfsDram d(p);
  auto l = d.locate(0x3ff);
  EXPECT_EQ(l.channel, 0u);
  EXPECT_EQ(l.bank, 0u);
  EXPECT_EQ(l.row, 0u);
  l = d.locate(0x400);
  EXPECT_EQ(l.channel, 1u);
  EXPECT_EQ(l.bank, 0u);
  l = d.locate(0x800);
  EXPECT_EQ(l.channel, 0u);
  EXPECT_EQ(l.bank, 1u);
  l = d.locate(8 * 1024 + 5);
  EXPECT_EQ(l.channel, 0u);
  EXPECT_EQ(l.bank, 0u);
  EXPECT_EQ(l.row, 1u);
}

TEST(DramTest, ValidationNamesTheKey) {
  DramParams p = small_dram();
  p.row_bytes = 100;
  try {
    validate(p, "dram");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("dram.row_bytes"), std::string::npos);
  }
}

class DramModuleTest : public testing::SystemCTest {};

TEST_F(DramModuleTest, FrFcfsThroughTlm) {
  const DramParams p = small_dram();
  const uint64_t rcd = p.tRCD_ps(), rp = p.tRP_ps(), cl = p.tCL_ps(), burst = p.burst_ps();
  testing::Requester req("req", {{0, kRow0Bank0, 64}, {1000, kRow1Bank0, 64},
                                 {2000, kRow0Bank0 + 128, 64}});
  req.expect_accepted = true;
  Dram dram("dram", p);
  req.socket.bind(dram.target_socket);
  sc_core::sc_start();
  const uint64_t ready = rcd + burst;
  EXPECT_EQ(req.done_ps[0], rcd + cl + burst);
  EXPECT_EQ(req.done_ps[2], std::max(ready + cl, rcd + cl + burst) + burst);  // hit first
  EXPECT_EQ(req.done_ps[1], ready + burst + rp + rcd + cl + burst);
  EXPECT_EQ(dram.horizon_ps(), MemoryHorizon::kNever);
}

}  // namespace
}  // namespace rtusim
