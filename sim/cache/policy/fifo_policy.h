// FIFO (round robin): the victim is the way filled longest ago; hits change nothing.
#pragma once
#include <cstdint>
#include <vector>

#include "cache/replacement_policy.h"

namespace rtusim {

class FifoPolicy final : public ReplacementPolicy {
 public:
  static constexpr const char* kName = "fifo";
  FifoPolicy(uint32_t sets, uint32_t ways, uint64_t /*seed*/) : ways_(ways), next_(sets, 0) {}

  const char* name() const override { return kName; }
  bool retouch_neutral() const override { return true; }  // hits change nothing
  void touch(uint32_t, uint32_t) override {}
  // Ways are filled in order (invalid ways lowest first, then the victims this policy names),
  // so the way after the one just filled is always the oldest.
  void fill(uint32_t set, uint32_t way) override { next_[set] = way + 1 == ways_ ? 0 : way + 1; }
  uint32_t victim(uint32_t set) override { return next_[set]; }

 private:
  uint32_t ways_;
  std::vector<uint32_t> next_;  // per set: the oldest way
};

}  // namespace rtusim
