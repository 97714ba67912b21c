// FrFcfsDram against a plain FR-FCFS scheduler written from its header's definition (every
// queued request looked at for every decision): on random request streams, driven as the Dram
// module and the timed engine drive it (enqueue at or after the last decision, advance at the
// next decision time), the same completions in the same order, the same next decision times and
// the same row counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <tuple>
#include <vector>

#include "mem/dram/fr_fcfs_dram.h"

namespace rtusim {
namespace {

class ReferenceFrFcfs {
 public:
  explicit ReferenceFrFcfs(const DramParams& p, const FrFcfsDram& mapping)
      : p_(p), mapping_(mapping), banks_(p.channels * p.banks), bus_free_(p.channels, 0) {}

  void enqueue(const DramRequest& r) { queue_.push_back({r, mapping_.locate(r.addr), seq_++}); }

  uint64_t next_decision_ps() const {
    uint64_t next = DramBackend::kNever;
    for (const Queued& q : queue_) next = std::min(next, eligible_at(q));
    return next;
  }

  void advance(uint64_t now_ps, std::vector<DramCompletion>& out) {
    for (uint32_t ch = 0; ch < p_.channels; ++ch) {
      for (;;) {
        // Row hits first, then age (arrival, address, enqueue order).
        size_t best = queue_.size();
        auto key = [&](const Queued& q) {
          return std::make_tuple(bank(q).open_row != q.loc.row, q.req.arrival_ps, q.req.addr,
                                 q.seq);
        };
        for (size_t i = 0; i < queue_.size(); ++i) {
          const Queued& q = queue_[i];
          if (q.loc.channel != ch || eligible_at(q) > now_ps) continue;
          if (best == queue_.size() || key(q) < key(queue_[best])) best = i;
        }
        if (best == queue_.size()) break;
        const Queued q = queue_[best];
        queue_.erase(queue_.begin() + static_cast<std::ptrdiff_t>(best));
        out.push_back({q.req.id, serve(q)});
      }
    }
  }

  uint64_t row_hits = 0, row_misses = 0, row_conflicts = 0;

 private:
  struct Queued {
    DramRequest req;
    FrFcfsDram::Location loc;
    uint64_t seq;
  };
  struct Bank {
    uint64_t open_row = ~uint64_t{0};
    uint64_t ready_ps = 0;
  };
  Bank& bank(const Queued& q) { return banks_[q.loc.channel * p_.banks + q.loc.bank]; }
  const Bank& bank(const Queued& q) const { return banks_[q.loc.channel * p_.banks + q.loc.bank]; }
  uint64_t eligible_at(const Queued& q) const {
    return std::max(q.req.arrival_ps, bank(q).ready_ps);
  }
  uint64_t serve(const Queued& q) {
    Bank& b = bank(q);
    uint64_t column = eligible_at(q);
    if (b.open_row == q.loc.row) {
      ++row_hits;
    } else if (b.open_row == ~uint64_t{0}) {
      ++row_misses;
      column += p_.tRCD_ps();
    } else {
      ++row_conflicts;
      column += p_.tRP_ps() + p_.tRCD_ps();
    }
    const uint64_t bursts =
        std::max<uint64_t>(1, (q.req.bytes + p_.burst_bytes() - 1) / p_.burst_bytes());
    uint64_t& bus = bus_free_[q.loc.channel];
    const uint64_t done = std::max(column + p_.tCL_ps(), bus) + bursts * p_.burst_ps();
    bus = done;
    b.open_row = q.loc.row;
    b.ready_ps = column + bursts * p_.burst_ps();
    return done;
  }

  DramParams p_;
  const FrFcfsDram& mapping_;
  std::vector<Bank> banks_;
  std::vector<uint64_t> bus_free_;
  std::vector<Queued> queue_;
  uint64_t seq_ = 0;
};

TEST(FrFcfsReferenceTest, RandomStreamsDecideAsThePlainScheduler) {
  for (const uint32_t channels : {1u, 2u}) {
    for (const uint32_t banks : {1u, 4u, 16u, 70u}) {
      DramParams p;
      p.channels = channels;
      p.banks = banks;
      p.row_bytes = 1024;
      FrFcfsDram d(p);
      ReferenceFrFcfs ref(p, d);
      std::mt19937_64 rng(channels * 1000 + banks);
      uint64_t now = 0, id = 0;
      std::vector<DramCompletion> got, want;
      for (int step = 0; step < 4000; ++step) {
        // A few reads arriving from now on (a leaf's triangles: one row, several lines), then
        // the decisions due before the next ones arrive.
        const int reads = static_cast<int>(rng() % 6);
        const uint64_t row_base = (rng() % (4 * banks * channels)) * 1024 * 4;
        for (int k = 0; k < reads; ++k) {
          const uint64_t addr = (rng() % 3 == 0 ? rng() % (64 * 1024 * banks * channels)
                                                : row_base + (rng() % 16) * 64) & ~uint64_t{63};
          const DramRequest r{id++, addr, rng() % 4 == 0 ? 32u : 64u, now + rng() % 20000,
                              static_cast<Stream>(rng() % 3)};
          d.enqueue(r);
          ref.enqueue(r);
        }
        ASSERT_EQ(d.next_decision_ps(), ref.next_decision_ps()) << "step " << step;
        const uint64_t until = now + rng() % 30000;
        while (d.next_decision_ps() <= until) {
          const uint64_t at = d.next_decision_ps();
          got.clear();
          want.clear();
          d.advance(at, got);
          ref.advance(at, want);
          ASSERT_EQ(got.size(), want.size()) << "step " << step;
          for (size_t i = 0; i < got.size(); ++i) {
            ASSERT_EQ(got[i].id, want[i].id) << "step " << step;
            ASSERT_EQ(got[i].done_ps, want[i].done_ps) << "step " << step;
          }
          ASSERT_EQ(d.next_decision_ps(), ref.next_decision_ps()) << "step " << step;
        }
        now = until;
      }
      EXPECT_EQ(d.row_hits(), ref.row_hits);
      EXPECT_EQ(d.row_misses(), ref.row_misses);
      EXPECT_EQ(d.row_conflicts(), ref.row_conflicts);
      EXPECT_GT(d.row_hits(), 0u);
      EXPECT_GT(d.row_conflicts(), 0u);
    }
  }
}

}  // namespace
}  // namespace rtusim
