// FastDivider against the divide instruction: divisors of every kind (powers of two, periods in
// picoseconds, odd and huge ones), numerators at the edges of each quotient and at random.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "mem/fast_divider.h"

namespace rtusim {
namespace {

void expect_exact(uint64_t d, uint64_t n) {
  const FastDivider f(d);
  ASSERT_EQ(f.div(n), n / d) << n << " / " << d;
  ASSERT_EQ(f.mod(n), n % d) << n << " % " << d;
}

TEST(FastDividerTest, MatchesDivisionForEveryKindOfDivisor) {
  std::vector<uint64_t> divisors = {1, 2, 3, 5, 7, 64, 72, 416, 625, 833, 1000, 1250, 8192,
                                    (uint64_t{1} << 32) + 1, ~uint64_t{0} / 3, ~uint64_t{0} - 1,
                                    ~uint64_t{0}, uint64_t{1} << 63, (uint64_t{1} << 63) + 1};
  std::mt19937_64 rng(11);
  for (int i = 0; i < 200; ++i) divisors.push_back(rng() >> (rng() % 64) | 1);
  for (uint64_t d : divisors) {
    // Around multiples of d (where a quotient one too small would show) and at the top.
    for (uint64_t k : {uint64_t{0}, uint64_t{1}, uint64_t{2}, uint64_t{1000}, ~uint64_t{0} / d})
      for (uint64_t delta : {uint64_t{0}, uint64_t{1}, d - 1})
        if (k * d + delta >= k * d) expect_exact(d, k * d + delta);
    expect_exact(d, ~uint64_t{0});
    expect_exact(d, ~uint64_t{0} - 1);
    for (int j = 0; j < 2000; ++j) expect_exact(d, rng() >> (rng() % 64));
  }
}

TEST(FastDividerTest, RoundsUp) {
  const FastDivider f(833);
  EXPECT_EQ(f.div_up(0), 0u);
  EXPECT_EQ(f.div_up(1), 1u);
  EXPECT_EQ(f.div_up(833), 1u);
  EXPECT_EQ(f.div_up(834), 2u);
  EXPECT_EQ(FastDivider(64).div_up(65), 2u);
}

}  // namespace
}  // namespace rtusim
