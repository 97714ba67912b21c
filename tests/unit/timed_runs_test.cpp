// The timed mode in runs (functional.timed_segments, TimedInterleaver): each run's window
// counts what happens between two cuts, so the runs' sums stay close to one model's figures;
// the warming rays are not counted; a batch too small for runs is one model's, exactly.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "app/pipeline.h"
#include "app/simulation.h"

namespace rtusim {
namespace {
namespace fs = std::filesystem;

class TimedRunsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    cfg_ = fs::temp_directory_path() / ("rtusim_timed_runs_" + std::to_string(::getpid()) + ".toml");
    std::ofstream(cfg_) << "[scene]\npath = \"builtin:cornell\"\n[image]\nwidth = 96\nheight = 96\n"
                           "[tracer]\nmax_depth = 4\nray_order = \"wavefront\"\n"
                           "[layout]\nkind = \"dfl\"\n[functional]\nrays_in_flight = 32\n"
                           "timed = true\n";
  }
  void TearDown() override { fs::remove(cfg_); }
  LayoutRun run(const std::vector<std::string>& overrides) {
    const SimulationResult r = simulate(prepare_run(cfg_.string(), overrides));
    EXPECT_EQ(r.layouts.size(), 1u);
    return r.layouts.front();
  }
  static double at(const LayoutRun& r, const char* key) { return r.stats.at(key).get<double>(); }
  fs::path cfg_;
};

TEST_F(TimedRunsTest, RunsAddUpToOneModelsFigures) {
  const LayoutRun one = run({});
  const LayoutRun runs = run({"functional.timed_segments=8", "functional.timed_warmup_rays=128"});
  EXPECT_FALSE(one.stats.values().contains("estimate.runs"));
  // 96 x 96 primary rays make 8 runs of >= 1024 rays; later batches fewer.
  ASSERT_TRUE(runs.stats.values().contains("estimate.runs"));
  EXPECT_GT(at(runs, "estimate.runs"), 8.0);
  EXPECT_EQ(at(runs, "functional.timed_segments"), 8.0);
  // Each fetch counted once, in the window of the cut it falls in: counting the warming rays
  // too would add about 7 x 128 rays' fetches to the primary batch alone (+10% of it).
  auto rel = [&](const char* key) { return at(runs, key) / at(one, key) - 1; };
  EXPECT_LT(std::abs(rel("traversal.node_fetches")), 2e-4) << rel("traversal.node_fetches");
  EXPECT_LT(std::abs(rel("traversal.triangle_fetches")), 5e-4);
  EXPECT_LT(std::abs(rel("dram.bytes.nodes")), 3e-3) << rel("dram.bytes.nodes");
  EXPECT_LT(std::abs(rel("dram.bytes.total")), 3e-3) << rel("dram.bytes.total");
  EXPECT_LT(std::abs(rel("estimate.cycles")), 3e-3) << rel("estimate.cycles");
  // The pixels' charges are the windows' bytes.
  const uint64_t sum = std::accumulate(runs.pixel_dram_bytes.begin(),
                                       runs.pixel_dram_bytes.end(), uint64_t{0});
  EXPECT_EQ(sum, runs.stats.at("dram.bytes.total").get<uint64_t>());
}

TEST_F(TimedRunsTest, SmallBatchesAreOneModelsExactly) {
  const LayoutRun one = run({});
  // 8 x 4096 rays a run: no batch of this frame is long enough.
  const LayoutRun runs = run({"functional.timed_segments=8", "functional.timed_warmup_rays=4096"});
  for (const auto& [key, value] : one.stats.values())
    if (key.find("seconds") == std::string::npos && key.find("per_second") == std::string::npos)
      EXPECT_EQ(value, runs.stats.at(key)) << key;
  // Only the keys saying so are added.
  EXPECT_EQ(runs.stats.values().size(), one.stats.values().size() + 2);
  EXPECT_TRUE(runs.stats.values().contains("estimate.runs"));
  EXPECT_EQ(one.pixel_dram_bytes, runs.pixel_dram_bytes);
}

}  // namespace
}  // namespace rtusim
