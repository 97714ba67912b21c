// The functional chip: the units' requests reach the shared L2 in turn order (hand-computed
// sequences), requests and bytes are conserved between levels, rays are dealt to units by tile
// or in runs, and a chip traces the frame tile by tile.
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "chip/chip_caches.h"
#include "chip/ray_dealer.h"

namespace rtusim {
namespace {

// Unit caches of one 64-byte line (direct-mapped: any other line evicts it), no data cache.
FetchCacheParams one_line_units() {
  FetchCacheParams p;
  p.node_l1 = CacheParams{.size_bytes = 64, .assoc = 1, .line_bytes = 64};
  return p;
}

ChipParams chip_with_l2(uint32_t units, uint64_t l2_bytes) {
  ChipParams c;
  c.units = units;
  c.l2 = CacheParams{.size_bytes = l2_bytes, .assoc = 1, .line_bytes = 64};
  return c;
}

TEST(ChipCaches, L2TakesRequestsOneFetchPerUnitInTurn) {
  // Each unit's L1 holds one line, the L2 one line. Unit 0 fetches A, B, A (three misses: B
  // evicts A), unit 1 fetches C, D, A. In turn order the L2 sees A C B D A A: the last A (unit
  // 1's third fetch) hits, right after unit 0's third. Unit by unit (A B A C D A) it would miss.
  const uint64_t A = 0, B = 64, C = 128, D = 192;
  ChipCaches chip(one_line_units(), chip_with_l2(2, 64), 16);
  for (uint64_t addr : {A, B, A}) chip.unit(0).fetch(Stream::kNode, addr, 8);
  chip.end_ray(0, 3);
  for (uint64_t addr : {C, D, A}) chip.unit(1).fetch(Stream::kNode, addr, 8);
  chip.end_ray(1, 5);
  chip.drain_all();
  EXPECT_EQ(chip.l2()->accesses(), 6u);
  EXPECT_EQ(chip.l2()->misses(), 5u);
  EXPECT_EQ(chip.l2_unit(0).misses, 3u);
  EXPECT_EQ(chip.l2_unit(1).hits, 1u);
  EXPECT_EQ(chip.l2_unit(1).misses, 2u);
  // Each pixel is charged the DRAM lines its rays' requests missed.
  EXPECT_EQ(chip.pixel_dram_bytes()[3], 3u * 64);
  EXPECT_EQ(chip.pixel_dram_bytes()[5], 2u * 64);
}

TEST(ChipCaches, TurnOrderDoesNotDependOnWhenTheL2Drains) {
  // The same requests, drained after every ray or once at the end: the same L2 counts.
  const auto run = [](bool drain_each_ray) {
    ChipCaches chip(one_line_units(), chip_with_l2(3, 128), 64);
    uint64_t x = 12345;
    for (int ray = 0; ray < 300; ++ray) {
      const uint32_t u = ray % 3;
      for (int f = 0; f < 1 + ray % 5; ++f) {
        x = x * 6364136223846793005ull + 1442695040888963407ull;
        chip.unit(u).fetch(static_cast<Stream>((x >> 60) % 3), (x >> 33) % 1024, 8);
      }
      chip.end_ray(u, ray % 64);
      if (drain_each_ray) chip.drain_ready();
    }
    chip.drain_all();
    return std::vector<uint64_t>{chip.l2()->accesses(), chip.l2()->misses(),
                                 chip.l2_unit(0).misses, chip.l2_unit(1).misses,
                                 chip.l2_unit(2).misses, chip.pixel_dram_bytes()[7]};
  };
  EXPECT_EQ(run(true), run(false));
}

TEST(ChipCaches, BytesAreConservedBetweenLevels) {
  FetchCacheParams p;
  p.node_l1 = CacheParams{.size_bytes = 256, .assoc = 2, .line_bytes = 32};
  p.dram_burst_bytes = 64;
  ChipCaches chip(p, chip_with_l2(2, 1024), 4);
  uint64_t x = 99;
  for (int i = 0; i < 2000; ++i) {
    x = x * 6364136223846793005ull + 1442695040888963407ull;
    const uint32_t u = i % 2;
    chip.unit(u).fetch(static_cast<Stream>((x >> 60) % 3), (x >> 30) % 8192, 12 + (x >> 20) % 40);
    chip.end_ray(u, i % 4);
  }
  chip.drain_all();
  // What the units sent (their L1 line misses and their bursts past the caches) is what the L2
  // took, and what it read from DRAM is its misses' lines, all charged to pixels.
  uint64_t sent = 0, taken = 0, dram = 0, charged = 0;
  for (const auto& c : chip.total_counters()) sent += c.dram_bytes;
  for (const auto& c : chip.l2_streams()) {
    taken += c.bytes_in;
    dram += c.dram_bytes;
  }
  for (uint64_t b : chip.pixel_dram_bytes()) charged += b;
  EXPECT_EQ(sent, taken);
  EXPECT_EQ(dram, chip.l2()->misses() * 64);
  EXPECT_EQ(charged, dram);
  EXPECT_GT(chip.l2()->hits(), 0u);
}

TEST(RayDealer, TilesRoundRobinInRowMajorOrder) {
  // 20x10 pixels, 8x8 tiles: 3 tiles per row (the last 4 wide), 2 rows; 4 units.
  ChipParams c;
  c.units = 4;
  c.tile_pixels = 8;
  RayDealer d(c, 20);
  EXPECT_EQ(d.next(0), 0u);            // (0,0): tile 0
  EXPECT_EQ(d.next(7), 0u);            // (7,0): tile 0
  EXPECT_EQ(d.next(8), 1u);            // (8,0): tile 1
  EXPECT_EQ(d.next(19), 2u);           // (19,0): tile 2
  EXPECT_EQ(d.next(8 * 20), 3u);       // (0,8): tile 3
  EXPECT_EQ(d.next(8 * 20 + 16), 1u);  // (16,8): tile 5 -> unit 1
}

TEST(RayDealer, BatchesAreRunsOfRaysDealtInTurn) {
  ChipParams c;
  c.units = 3;
  c.distribution = RayDistribution::kBatches;
  c.batch_rays = 2;
  RayDealer d(c, 100);
  std::vector<uint32_t> units;
  for (int i = 0; i < 8; ++i) units.push_back(d.next(99));  // the pixel does not matter
  EXPECT_EQ(units, (std::vector<uint32_t>{0, 0, 1, 1, 2, 2, 0, 0}));
}

TEST(ChipPixelOrder, TileByTileOnAChipScanOrderElse) {
  // 5x3 pixels, 2x2 tiles: tiles (0,0) (2,0) (4,0) then (0,2) (2,2) (4,2), each row by row.
  ChipParams c;
  c.units = 2;
  c.tile_pixels = 2;
  EXPECT_EQ(chip_pixel_order(c, 5, 3),
            (std::vector<uint32_t>{0, 1, 5, 6, 2, 3, 7, 8, 4, 9, 10, 11, 12, 13, 14}));
  c.distribution = RayDistribution::kBatches;
  EXPECT_TRUE(chip_pixel_order(c, 5, 3).empty());
  c = ChipParams{};  // one unit, no L2: the simulator's own order
  EXPECT_TRUE(chip_pixel_order(c, 5, 3).empty());
}

}  // namespace
}  // namespace rtusim
