// Sampled simulation's parts: the unit plan partitions the frame and draws strata in
// proportion; the estimator's totals, CIs, census and validity flags; the paired layout
// difference's CI against one computed here from the units' known figures.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "app/pipeline.h"
#include "sample/estimator.h"
#include "sample/sampled_frame.h"
#include "sample/unit_plan.h"
#include "tracer/hit_backend.h"
#include "util/stats.h"

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

// The fallback when a stratum has fewer than two units: one simple random sample of the whole
// population, finite-population corrected, by hand: values 1, 3, 10 of N = 110 units; mean
// 14/3, s^2 = (121/9 + 25/9 + 256/9) / 2 = 67/3; Var = 110^2 (1 - 3/110) (67/3) / 3 =
// 110 x 107 x 67 / 9 = 788590 / 9; t(2) = 4.303. Without the correction: 1291.4, not 1273.7.
TEST(SampleEstimator, FallbackWithALoneStratumIsOneCorrectedSample) {
  const Estimate lone = Estimator({100.0, 10.0}, 2).total({1, 3, 10}, {0, 0, 1});
  EXPECT_NEAR(lone.value, 110.0 * 14.0 / 3.0, 1e-9);
  EXPECT_NEAR(lone.half_width, 4.303 * std::sqrt(788590.0 / 9.0), 1e-9);
  EXPECT_NEAR(lone.half_width, 1273.73, 0.01);
  EXPECT_FALSE(lone.valid);
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

// A tier whose one figure, dram.bytes.nodes, is known per pixel: each primary ray of pixel p
// adds weight(p). Its backend finds the rays' hits by plain traversal (the tracer needs them).
class PixelWeightTier final : public TierRun, public TraceBackend {
 public:
  PixelWeightTier(const MemoryImage& image, std::function<double(uint32_t)> weight)
      : host_(image), weight_(std::move(weight)) {}
  TraceBackend& backend() override { return *this; }
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override {
    host_.trace(rays, hits);
    for (const RayRecord& r : rays)
      if (r.kind == RayKind::kPrimary) bytes_ += weight_(r.pixel);
  }
  void write_stats(Stats& stats) const override { stats.set("dram.bytes.nodes", bytes_); }

 private:
  HitBackend host_;
  std::function<double(uint32_t)> weight_;
  double bytes_ = 0.0;
};

// The paired ODFL - DFL difference over the same units: its CI is the stratified estimator's
// over the per-unit differences, computed here from the units' known figures (Cochran 5.6 with
// the finite-population correction, Student's t with n - H df). Layouts whose figures move
// together have a far narrower paired CI than the unpaired sqrt(hw_a^2 + hw_b^2).
TEST(SampledFrame, PairedDifferenceCiFromTheUnitsDifferences) {
  constexpr int kW = 32, kH = 16;
  const std::filesystem::path cfg = std::filesystem::temp_directory_path() /
                                    ("rtusim_paired_" + std::to_string(::getpid()) + ".toml");
  std::ofstream(cfg) << "[scene]\npath = \"builtin:cornell\"\n[image]\nwidth = " << kW
                     << "\nheight = " << kH << "\n[tracer]\nmax_depth = 1\n";
  const Prepared p = prepare_run(cfg.string(), {});
  std::filesystem::remove(cfg);
  SampleParams sp;
  sp.rate = 0.5;
  sp.method = SampleMethod::kTiles;
  sp.method_name = "tiles";
  sp.unit_pixels = 8;
  sp.strata = 2;
  sp.min_units = 2;
  sp.warmup = SampleWarmup::kNone;
  sp.warmup_name = "none";
  // DFL's bytes vary from pixel to pixel; ODFL's are about twice DFL's, plus a little.
  const auto dfl = [](uint32_t px) { return double((px * 7919u) % 101u); };
  const auto odfl = [&](uint32_t px) { return 2.0 * dfl(px) + double(px % 5u); };
  SampledFrame frame(sp, kW, kH, RayOrder::kRecursive);
  const PinholeCamera camera(p.camera, kW, kH);
  double seconds = 0.0;
  Stats stats;
  std::map<std::string, Estimate> alone;  // each layout's own estimate, for the unpaired width
  for (const auto& [name, weight] : {std::pair<std::string, std::function<double(uint32_t)>>{"dfl", dfl},
                                     {"odfl", odfl}}) {
    PixelWeightTier tier(p.images[0], weight);
    FrameResult f = frame.render(p.scene, p.config.tracer, camera, tier, p.images[0], name, seconds);
    Stats s;
    tier.write_stats(s);
    frame.finish_layout(f, s);
    const double v = s.at("dram.bytes.nodes").get<double>();
    alone[name] = Estimate{.value = v,
                           .half_width = s.at("dram.bytes.nodes.ci95_high").get<double>() - v};
  }
  frame.write_run_stats(stats);

  // The drawn units (the plan's first half) and their differences, by stratum.
  const UnitPlan plan = make_unit_plan(sp, kW, kH);
  const size_t n = plan.size() / 2;
  ASSERT_EQ(plan.stratum_units.size(), 4u);
  std::vector<std::vector<double>> d(4);
  for (size_t i = 0; i < n; ++i) {
    const uint32_t u = plan.order[i];
    double sum = 0.0;
    for (const uint32_t px : plan.units[u]) sum += odfl(px) - dfl(px);
    d[plan.stratum[u]].push_back(sum);
  }
  double total = 0.0, variance = 0.0;
  for (size_t h = 0; h < 4; ++h) {
    const double big_n = plan.stratum_units[h], nh = double(d[h].size());
    ASSERT_GE(nh, 2.0);
    double mean = 0.0, ss = 0.0;
    for (const double x : d[h]) mean += x / nh;
    for (const double x : d[h]) ss += (x - mean) * (x - mean);
    total += big_n * mean;
    variance += big_n * big_n * (1.0 - nh / big_n) * ss / (nh - 1.0) / nh;
  }
  const double half_width = t_quantile_95(int(n) - 4) * std::sqrt(variance);
  const std::string key = "sample.diff.odfl-dfl.dram.bytes.nodes";
  EXPECT_NEAR(stats.at(key).get<double>(), total, 1e-6 * std::abs(total));
  EXPECT_NEAR(stats.at(key + ".ci95_high").get<double>() - total, half_width, 1e-6 * half_width);
  EXPECT_NEAR(total - stats.at(key + ".ci95_low").get<double>(), half_width, 1e-6 * half_width);
  // The case tells the paired width from the unpaired one.
  EXPECT_GT(std::hypot(alone["dfl"].half_width, alone["odfl"].half_width), 2.0 * half_width);
}

}  // namespace
}  // namespace rtusim
