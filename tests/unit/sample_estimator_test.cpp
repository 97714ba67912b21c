// Sampled simulation's parts: the unit plan partitions the frame and draws strata in
// proportion; the estimator's totals, CIs, census and validity flags.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "sample/estimator.h"
#include "sample/unit_plan.h"

namespace rtusim {
namespace {

TEST(SampleEstimator, TQuantile) {
  EXPECT_NEAR(t_quantile_95(1), 12.706, 1e-3);
  EXPECT_NEAR(t_quantile_95(30), 2.042, 1e-3);
  EXPECT_NEAR(t_quantile_95(60), 2.000, 1e-3);
  EXPECT_NEAR(t_quantile_95(100000), 1.960, 1e-3);
}

TEST(SampleEstimator, SimpleRandomSampleTotalAndCi) {
  const Estimator e({10.0}, 2);
  const Estimate t = e.total({1, 2, 3, 4}, {0, 0, 0, 0});
  EXPECT_DOUBLE_EQ(t.value, 25.0);  // 10 units x mean 2.5
  // Var = N^2 (1 - n/N) s^2 / n = 100 x 0.6 x (5/3) / 4 = 25; t(3) = 3.182.
  EXPECT_NEAR(t.half_width, 3.182 * 5.0, 1e-9);
  EXPECT_TRUE(t.valid);
}

TEST(SampleEstimator, CensusHasNoWidth) {
  const Estimator e({2.0, 3.0}, 2);
  const Estimate t = e.total({1, 5, 2, 2, 8}, {0, 0, 1, 1, 1});
  EXPECT_DOUBLE_EQ(t.value, 18.0);
  EXPECT_DOUBLE_EQ(t.half_width, 0.0);
  // A census of one unit, or of fewer than min_units: exact and valid (it had an open CI).
  const Estimate one = Estimator({1.0}, 30).total({7}, {0});
  EXPECT_DOUBLE_EQ(one.value, 7.0);
  EXPECT_DOUBLE_EQ(one.half_width, 0.0);
  EXPECT_TRUE(one.valid) << one.problem;
}

TEST(SampleEstimator, StratifiedWeightsAndFlags) {
  const Estimator e({100.0, 10.0}, 5);
  const Estimate t = e.total({1, 3, 10, 10}, {0, 0, 1, 1});
  EXPECT_DOUBLE_EQ(t.value, 100.0 * 2.0 + 10.0 * 10.0);
  EXPECT_FALSE(t.valid);  // 4 units < 5
  const Estimate lone = Estimator({100.0, 10.0}, 2).total({1, 3, 10}, {0, 0, 1});
  EXPECT_FALSE(lone.valid);  // stratum 1 has one unit
  EXPECT_NE(lone.problem.find("stratum"), std::string::npos);
}

// The ratio estimator: X x (sum y / sum x); its width comes from the residuals y - R x, so a
// figure proportional to x has none, and one that follows x loosely is narrower than the mean's.
TEST(SampleEstimator, RatioEstimator) {
  const Estimator e({10.0}, 2);
  const Estimate exact = e.ratio({2, 4, 6, 8}, {1, 2, 3, 4}, 40.0, {0, 0, 0, 0});
  EXPECT_DOUBLE_EQ(exact.value, 80.0);  // y = 2 x everywhere: 2 x the frame's 40
  EXPECT_NEAR(exact.half_width, 0.0, 1e-9);
  const std::vector<double> y{2.5, 3.5, 6.5, 7.5}, x{1, 2, 3, 4};
  const Estimate r = e.ratio(y, x, 25.0, {0, 0, 0, 0});
  EXPECT_DOUBLE_EQ(r.value, 25.0 * 20.0 / 10.0);
  // Residuals y - 2x: 0.5, -0.5, 0.5, -0.5 -> s^2 = 1/3; Var = 100 x 0.6 x (1/3) / 4 = 5.
  EXPECT_NEAR(r.half_width, 3.182 * std::sqrt(5.0), 1e-9);
  EXPECT_LT(r.half_width, e.total(y, {0, 0, 0, 0}).half_width);
  // A frame with twice the rays the sample implies: the variance scaled by (X / X_hat)^2 = 4.
  EXPECT_NEAR(e.ratio(y, x, 50.0, {0, 0, 0, 0}).half_width, 2.0 * r.half_width, 1e-9);
  EXPECT_TRUE(r.valid);
  EXPECT_FALSE(Estimator({10.0}, 5).ratio(y, x, 25.0, {0, 0, 0, 0}).valid);  // 4 units < 5
}

// Every method splits the frame into units that hold each pixel once; the first tenth of the
// stratified and tiles orders takes each stratum in proportion.
TEST(SampleUnitPlan, PartitionsTheFrameAndDrawsInProportion) {
  for (const SampleMethod m : {SampleMethod::kRandom, SampleMethod::kStratified, SampleMethod::kTiles}) {
    SampleParams s;
    s.method = m;
    s.unit_pixels = 7;
    s.strata = 3;
    const UnitPlan plan = make_unit_plan(s, 30, 21);
    std::vector<int> seen(30 * 21, 0);
    for (const auto& unit : plan.units) {
      EXPECT_TRUE(std::is_sorted(unit.begin(), unit.end()));
      for (uint32_t p : unit) ++seen[p];
    }
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int c) { return c == 1; }));
    std::vector<uint32_t> order = plan.order;
    std::sort(order.begin(), order.end());
    for (uint32_t i = 0; i < order.size(); ++i) ASSERT_EQ(order[i], i);
    for (double units : plan.stratum_units) EXPECT_GT(units, 0.0);
    if (m != SampleMethod::kRandom) {
      ASSERT_EQ(plan.stratum_units.size(), 9u);
      std::vector<int> taken(9, 0);
      const size_t n = plan.size() / 10;
      for (size_t i = 0; i < n; ++i) ++taken[plan.stratum[plan.order[i]]];
      for (int h = 0; h < 9; ++h)
        EXPECT_NEAR(taken[h], plan.stratum_units[h] * double(n) / plan.size(), 1.0) << h;
    }
  }
}

}  // namespace
}  // namespace rtusim
