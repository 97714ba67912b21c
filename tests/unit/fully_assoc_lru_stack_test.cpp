// FullyAssocLruStack against a plain LRU list: each access's region equals the capacity index
// its stack distance reaches.
#include "sweep/fully_assoc_lru_stack.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace rtusim {
namespace {

TEST(FullyAssocLruStack, RegionsEqualAPlainLruList) {
  // Capacities small and large, and a largest capacity above the lines there are; each
  // access's region against its distance in a plain LRU list.
  const std::vector<std::vector<uint64_t>> capacity_sets = {
      {1}, {3, 7}, {8, 16, 32}, {5, 31, 33}, {32, 64, 200}, {40, 41, 90, 1000}, {2, 33, 300}};
  for (const auto& caps : capacity_sets) {
    const uint32_t lines = 400;
    FullyAssocLruStack stack(caps, lines);
    std::vector<uint32_t> list;  // most recent first
    std::mt19937 rng(static_cast<uint32_t>(caps.size() * 31 + caps.back()));
    uint32_t line = 0;
    for (int i = 0; i < 60000; ++i) {
      const uint32_t r = rng() % 100;
      if (r < 50) line = (line + rng() % 5) % lines;
      else if (r < 80 && !list.empty()) line = list[rng() % std::min<size_t>(list.size(), 80)];
      else line = rng() % lines;
      const auto at = std::find(list.begin(), list.end(), line);
      const size_t distance = at == list.end() ? SIZE_MAX : static_cast<size_t>(at - list.begin());
      uint32_t expected = 0;
      while (expected < caps.size() && distance >= caps[expected]) ++expected;
      ASSERT_EQ(stack.access(line), expected)
          << "access " << i << ", capacities up to " << caps.back();
      if (at != list.end()) list.erase(at);
      list.insert(list.begin(), line);
    }
  }
}

}  // namespace
}  // namespace rtusim
