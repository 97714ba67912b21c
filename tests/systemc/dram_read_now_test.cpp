// DramBackend::read_now, the timed interleaver's one-read-at-a-time DRAM call: each model's fast
// path gives, read after read, the completion times and stats of enqueue then advance (the
// base class's read_now), and refuses to run beside queued requests.
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "mem/dram/dram_backends.h"
#include "util/stats.h"

namespace rtusim {
namespace {

// A model seen through the base class's read_now only: enqueue, then advance.
class QueuedOnly final : public DramBackend {
 public:
  explicit QueuedOnly(std::unique_ptr<DramBackend> m) : m_(std::move(m)) {}
  void enqueue(const DramRequest& r) override { m_->enqueue(r); }
  uint64_t next_decision_ps() const override { return m_->next_decision_ps(); }
  void advance(uint64_t now_ps, std::vector<DramCompletion>& out) override {
    m_->advance(now_ps, out);
  }
  void write_stats(Stats& stats, const std::string& prefix) const override {
    m_->write_stats(stats, prefix);
  }

 private:
  std::unique_ptr<DramBackend> m_;
};

// Two channels, 4 banks, 1 KB rows: a few rows per bank, so hits, misses and conflicts mix.
DramParams small_dram(const std::string& backend) {
  DramParams p;
  p.backend = backend;
  p.channels = 2;
  p.banks = 4;
  p.row_bytes = 1024;
  return p;
}

Stats stats_of(const DramBackend& d) {
  Stats s;
  d.write_stats(s, "dram");
  return s;
}

TEST(DramReadNowTest, SameAsEnqueueThenAdvanceForEveryModel) {
  for (const std::string& name : DramBackends::names()) {
    SCOPED_TRACE(name);
    const DramParams p = small_dram(name);
    std::unique_ptr<DramBackend> fast = make_dram_backend(p);
    QueuedOnly queued(make_dram_backend(p));
    std::mt19937_64 rng(12);
    const uint32_t sizes[] = {0, 32, 64, 100, 128, 256};
    const Stream streams[] = {Stream::kNode, Stream::kList, Stream::kTriangle};
    uint64_t base_ps = 0;
    for (uint64_t id = 0; id < 5000; ++id) {
      // Arrivals mostly later than the last, sometimes earlier (the interleaver's reads are
      // sent at their ray's cycle, not in order); some close enough to queue on the bus.
      base_ps += rng() % 6000;
      const DramRequest r{id, (rng() % (2 * 1024 * 2 * 4 * 3)) & ~uint64_t{31}, sizes[rng() % 6],
                          base_ps + rng() % 20000, streams[rng() % 3]};
      ASSERT_EQ(fast->read_now(r), queued.read_now(r)) << "read " << id;
      ASSERT_EQ(fast->next_decision_ps(), DramBackend::kNever);
    }
    const Stats a = stats_of(*fast), b = stats_of(queued);
    EXPECT_EQ(a.to_json(), b.to_json());
    EXPECT_EQ(a.at("dram.requests").get<uint64_t>(), 5000u);
    if (name == FrFcfsDram::kName) {  // rows open once per bank, then hit or conflict
      EXPECT_EQ(a.at("dram.row_misses").get<uint64_t>(), 2u * 4);
      EXPECT_GT(a.at("dram.row_hits").get<uint64_t>(), 500u);
      EXPECT_GT(a.at("dram.row_conflicts").get<uint64_t>(), 500u);
    }
  }
}

TEST(DramReadNowTest, RefusedBesideQueuedRequests) {
  for (const std::string& name : DramBackends::names()) {
    SCOPED_TRACE(name);
    std::unique_ptr<DramBackend> fast = make_dram_backend(small_dram(name));
    QueuedOnly queued(make_dram_backend(small_dram(name)));
    for (DramBackend* d : {fast.get(), static_cast<DramBackend*>(&queued)}) {
      d->enqueue({1, 0, 64, 1000, Stream::kNode});
      EXPECT_THROW(d->read_now({2, 64, 64, 1000, Stream::kNode}), std::logic_error);
    }
  }
}

}  // namespace
}  // namespace rtusim
