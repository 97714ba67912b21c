// Heatmaps: each pixel's DRAM bytes add up to the layout's dram.bytes.total, and the colourings
// put the right colour on the right pixel (not just a non-empty PNG); the PNGs `rtusim run`
// writes, decoded, hold pixel by pixel the colours of the run's per-pixel bytes.
#include "image/heatmap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <stb_image.h>
#include <unistd.h>

#include "app/commands.h"
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

// The heat scale as heatmap.h states it, written here: log1p(bytes) / log1p(max) along eight
// inferno stops, interpolated linearly, rounded.
std::array<int, 3> heat_colour(uint64_t bytes, uint64_t max_bytes) {
  static constexpr double kStops[8][3] = {{0, 0, 4},     {40, 11, 84},  {101, 21, 110},
                                          {159, 42, 99}, {212, 72, 66}, {245, 125, 21},
                                          {250, 193, 39}, {252, 255, 164}};
  const double v = std::log1p(double(bytes)) / std::log1p(double(std::max<uint64_t>(1, max_bytes)));
  const double x = std::clamp(v, 0.0, 1.0) * 7;
  const int i = std::min(int(x), 6);
  const double f = x - i;
  std::array<int, 3> rgb{};
  for (int c = 0; c < 3; ++c) rgb[c] = int(std::lround(kStops[i][c] * (1 - f) + kStops[i + 1][c] * f));
  return rgb;
}

// The difference map's colour of b - a: white when equal, towards red when b is more, blue when
// less, sqrt-faded, saturated at the largest |b - a| (at least 1).
std::array<int, 3> diff_colour(uint64_t a, uint64_t b, double max_abs) {
  const double d = (double(b) - double(a)) / max_abs;
  const int c = int(std::lround(255.0 * (1.0 - std::sqrt(std::abs(d)))));
  return {d > 0 ? 255 : c, c, d < 0 ? 255 : c};
}

struct Png {
  int w = 0, h = 0;
  std::vector<unsigned char> rgb;
  std::array<int, 3> at(int x, int y) const {
    const unsigned char* p = &rgb[(size_t(y) * w + x) * 3];
    return {p[0], p[1], p[2]};
  }
};

Png read_png(const std::filesystem::path& path) {
  Png png;
  int channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &png.w, &png.h, &channels, 3);
  if (!data) return png;
  png.rgb.assign(data, data + size_t(png.w) * png.h * 3);
  stbi_image_free(data);
  return png;
}

// `rtusim run` with three layouts: each heatmap_<kind>.png is, pixel by pixel, the heat colour
// of that layout's bytes (from simulate(), on a scale topped by the maximum over the layouts),
// and diff_odfl_dfl.png the difference colour of ODFL's minus DFL's: so a map of another layout,
// a flipped byte, or a diff map of one colour fails. The case has pixels of each kind.
TEST(HeatmapTest, RunWritesTheBytesColoursPixelByPixel) {
  constexpr int kW = 40, kH = 30;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("rtusim_heatmap_run_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::filesystem::path cfg = dir / "run.toml";
  std::ofstream(cfg) << "[scene]\npath = \"builtin:cornell\"\n[image]\nwidth = " << kW
                     << "\nheight = " << kH << "\npng = false\n[tracer]\nmax_depth = 4\n"
                        "[layout]\nkind = [\"dfl\", \"odfl\", \"subtree\"]\n";
  const SimulationResult r = simulate(prepare_run(cfg.string(), {}));
  ASSERT_EQ(run_command(RunOptions{.config = cfg.string(), .out = (dir / "out").string()}), 0);
  uint64_t max_bytes = 1;
  for (const LayoutRun& run : r.layouts)
    for (const uint64_t b : run.pixel_dram_bytes) max_bytes = std::max(max_bytes, b);
  const std::vector<uint64_t>* bytes_of[2] = {nullptr, nullptr};  // dfl, odfl
  for (const LayoutRun& run : r.layouts) {
    SCOPED_TRACE(run.kind);
    ASSERT_EQ(run.pixel_dram_bytes.size(), size_t(kW) * kH);
    if (run.kind == "dfl") bytes_of[0] = &run.pixel_dram_bytes;
    if (run.kind == "odfl") bytes_of[1] = &run.pixel_dram_bytes;
    const Png map = read_png(dir / "out" / ("heatmap_" + run.kind + ".png"));
    ASSERT_EQ(map.w, kW);
    ASSERT_GT(map.h, kH);  // the colour scale below
    int wrong = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const uint64_t b = run.pixel_dram_bytes[size_t(y) * kW + x];
        if (map.at(x, y) == heat_colour(b, max_bytes)) continue;
        if (++wrong <= 3) ADD_FAILURE() << "pixel " << x << "," << y << ": " << b << " bytes";
      }
    EXPECT_EQ(wrong, 0);
  }
  ASSERT_TRUE(bytes_of[0] && bytes_of[1]);
  const std::vector<uint64_t>&a = *bytes_of[0], &b = *bytes_of[1];
  double max_abs = 1.0;
  for (size_t i = 0; i < a.size(); ++i) max_abs = std::max(max_abs, std::abs(double(b[i]) - double(a[i])));
  const Png diff = read_png(dir / "out" / "diff_odfl_dfl.png");
  ASSERT_EQ(diff.w, kW);
  ASSERT_EQ(diff.h, kH);
  int wrong = 0, more = 0, fewer = 0, equal = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const size_t i = size_t(y) * kW + x;
      more += b[i] > a[i], fewer += b[i] < a[i], equal += b[i] == a[i];
      if (diff.at(x, y) == diff_colour(a[i], b[i], max_abs)) continue;
      if (++wrong <= 3) ADD_FAILURE() << "diff pixel " << x << "," << y << ": " << a[i] << " -> " << b[i];
    }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(more, 0);
  EXPECT_GT(fewer, 0);
  EXPECT_GT(equal, 0);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rtusim
