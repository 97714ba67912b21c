// Random replacement, deterministic: one splitmix64 stream per cache, seeded from `seed`, drawn
// once per eviction, so a run is the same on every machine and every repetition.
#pragma once
#include <cstdint>

#include "cache/replacement_policy.h"

namespace rtusim {

// splitmix64 (Steele, Lea, Flood 2014): a 64-bit counter through a mixing function.
class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, n) for n < 2^32: the top 32 bits scaled (Lemire), no division.
  uint32_t below(uint32_t n) { return static_cast<uint32_t>(((next() >> 32) * n) >> 32); }

 private:
  uint64_t state_;
};

class RandomPolicy final : public ReplacementPolicy {
 public:
  static constexpr const char* kName = "random";
  RandomPolicy(uint32_t /*sets*/, uint32_t ways, uint64_t seed) : ways_(ways), rng_(seed) {}

  const char* name() const override { return kName; }
  bool retouch_neutral() const override { return true; }  // hits change nothing
  void touch(uint32_t, uint32_t) override {}
  void fill(uint32_t, uint32_t) override {}
  uint32_t victim(uint32_t) override { return rng_.below(ways_); }

 private:
  uint32_t ways_;
  SplitMix64 rng_;
};

}  // namespace rtusim
