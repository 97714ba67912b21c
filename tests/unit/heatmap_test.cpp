// Heatmaps: each pixel's DRAM bytes add up to the layout's dram.bytes.total, and the colourings
// put the right colour on the right pixel (not just a non-empty PNG).
#include "image/heatmap.h"

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

// Every ray's traffic is attributed to its pixel: the per-pixel bytes of each layout sum to that
// layout's total, with every pixel present (none dropped); also when rays interleave (charged
// when each ends: round-robin, and the timed mode; in runs, each window's bytes).
TEST(HeatmapTest, PixelBytesAddUpToTheLayoutsDramTotal) {
  const fs::path cfg = fs::temp_directory_path() / ("rtusim_heatmap_" + std::to_string(::getpid()) + ".toml");
  std::ofstream(cfg) << "[scene]\npath = \"builtin:cornell\"\n[image]\nwidth = 40\nheight = 30\n"
                        "[tracer]\nmax_depth = 4\n[layout]\nkind = [\"dfl\", \"odfl\", \"subtree\"]\n";
  const std::vector<std::vector<std::string>> modes = {
      {},
      {"tracer.ray_order=wavefront", "functional.rays_in_flight=8"},
      {"tracer.ray_order=wavefront", "functional.rays_in_flight=8", "functional.timed=true"},
      {"tracer.ray_order=wavefront", "functional.rays_in_flight=8", "functional.timed=true",
       "functional.timed_segments=4", "functional.timed_warmup_rays=32"}};
  for (const auto& mode : modes) {
    const Prepared p = prepare_run(cfg.string(), mode);
    const SimulationResult r = simulate(p);
    ASSERT_EQ(r.layouts.size(), 3u);
    for (const LayoutRun& run : r.layouts) {
      ASSERT_EQ(run.pixel_dram_bytes.size(), 40u * 30u) << run.kind;
      const uint64_t sum = std::accumulate(run.pixel_dram_bytes.begin(),
                                           run.pixel_dram_bytes.end(), uint64_t{0});
      EXPECT_EQ(sum, run.stats.at("dram.bytes.total").get<uint64_t>()) << run.kind;
      EXPECT_GT(sum, 0u);
    }
  }
  fs::remove(cfg);
}

// The scale runs from near-black (0 bytes) to pale yellow (the maximum), brighter with more bytes,
// on a log scale: 0, 1, the maximum at the two ends and in between pixel by pixel.
TEST(HeatmapTest, HeatColoursFollowTheBytes) {
  const std::vector<uint64_t> bytes = {0, 1000, 10, 1000000, 100};
  const auto rgb = heatmap_rgb8(bytes, 1000000);
  ASSERT_EQ(rgb.size(), bytes.size() * 3);
  auto px = [&](size_t i) { return std::vector<int>{rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]}; };
  EXPECT_EQ(px(0), (std::vector<int>{0, 0, 4}));
  EXPECT_EQ(px(3), (std::vector<int>{252, 255, 164}));
  auto lum = [&](size_t i) { return rgb[3 * i] + rgb[3 * i + 1] + rgb[3 * i + 2]; };
  EXPECT_LT(lum(0), lum(2));
  EXPECT_LT(lum(2), lum(4));
  EXPECT_LT(lum(4), lum(1));
  EXPECT_LT(lum(1), lum(3));
}

// ODFL - DFL: red where ODFL moves more, blue where fewer, white where equal; the largest
// difference fully saturated.
TEST(HeatmapTest, DifferenceColoursHaveTheRightSign) {
  const std::vector<uint64_t> dfl = {100, 100, 100, 50};
  const std::vector<uint64_t> odfl = {100, 200, 50, 50};
  const auto rgb = difference_rgb8(dfl, odfl);
  auto px = [&](size_t i) { return std::vector<int>{rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]}; };
  EXPECT_EQ(px(0), (std::vector<int>{255, 255, 255}));
  EXPECT_EQ(px(1), (std::vector<int>{255, 0, 0}));  // +100, the largest: pure red
  EXPECT_EQ(px(2)[2], 255);                          // -50: blue ...
  EXPECT_LT(px(2)[0], 255);                          // ... not white
  EXPECT_EQ(px(2)[0], px(2)[1]);
  EXPECT_EQ(px(3), (std::vector<int>{255, 255, 255}));
}

}  // namespace
}  // namespace rtusim
