// The chip's keys (chip.*) and the shared L2's (l2.*).
#include "chip/chip_params.h"

#include "cache/cache_config.h"
#include "config/param.h"

namespace rtusim {
namespace {

const ChipParams kChip;
const IntParam kUnits("chip.units", kChip.units, 1, 1024, "units",
                      "traversal units, each with its own node L1 and data cache (l1.*, "
                      "dcache.*)");
const StringParam kDistribution("chip.distribution", "tiles", {"tiles", "batches"}, "",
                                "which unit traces a ray: tiles (screen tiles of "
                                "chip.tile_pixels squared dealt round-robin, each unit tracing "
                                "its pixels' whole ray trees) or batches (the frame's rays in "
                                "order, in runs of chip.batch_rays dealt round-robin)");
const IntParam kTilePixels("chip.tile_pixels", kChip.tile_pixels, 1, 16384, "pixels",
                           "side of a screen tile (chip.distribution = tiles)");
const IntParam kBatchRays("chip.batch_rays", kChip.batch_rays, 1, 1 << 24, "rays",
                          "rays a unit takes in turn (chip.distribution = batches)");
const BoolParam kL2Enable("l2.enable", false,
                          "an L2 shared by every unit's caches in front of DRAM (false: the "
                          "units' caches read DRAM directly)");
const CacheLevelKeys kL2Keys("l2", "shared L2",
                             CacheParams{.size_bytes = uint64_t{1} << 20, .assoc = 16});

}  // namespace

ChipParams read_chip_params(ConfigReader& r) {
  ChipParams c;
  c.units = static_cast<uint32_t>(kUnits.read(r));
  c.distribution =
      kDistribution.read(r) == "tiles" ? RayDistribution::kTiles : RayDistribution::kBatches;
  c.tile_pixels = static_cast<uint32_t>(kTilePixels.read(r));
  c.batch_rays = static_cast<uint32_t>(kBatchRays.read(r));
  const bool l2 = kL2Enable.read(r);
  const CacheParams l2_cache = kL2Keys.read(r);
  if (l2) c.l2 = l2_cache;
  return c;
}

}  // namespace rtusim
