// True LRU: every way carries the time of its last use; the victim is the least recent.
#pragma once
#include <cstdint>
#include <vector>

#include "cache/replacement_policy.h"

namespace rtusim {

class LruPolicy final : public ReplacementPolicy {
 public:
  static constexpr const char* kName = "lru";
  LruPolicy(uint32_t sets, uint32_t ways, uint64_t /*seed*/)
      : ways_(ways), last_use_(uint64_t{sets} * ways, 0) {}

  const char* name() const override { return kName; }
  bool retouch_neutral() const override { return true; }  // the last-used way stays the most recent
  void touch(uint32_t set, uint32_t way) override {
    last_use_[uint64_t{set} * ways_ + way] = ++clock_;
  }
  void fill(uint32_t set, uint32_t way) override { touch(set, way); }
  uint32_t victim(uint32_t set) override {
    const uint64_t* t = &last_use_[uint64_t{set} * ways_];
    uint32_t oldest = 0;
    uint64_t oldest_use = t[0];
    for (uint32_t w = 1; w < ways_; ++w) {  // selects, not branches: the outcome is random
      const bool older = t[w] < oldest_use;
      oldest_use = older ? t[w] : oldest_use;
      oldest = older ? w : oldest;
    }
    return oldest;
  }

 private:
  uint32_t ways_;
  uint64_t clock_ = 0;              // one tick per touch or fill: times are unique
  std::vector<uint64_t> last_use_;  // [set * ways + way]
};

}  // namespace rtusim
