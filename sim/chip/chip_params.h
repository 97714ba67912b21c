// The chip: how many traversal units there are, how the frame's rays are dealt to them, and the
// shared L2 in front of DRAM. Declared once here (chip.*, l2.*) and built by the tiers from this
// one description; each unit has the private caches of l1.* and dcache.*.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "cache/cache_params.h"

namespace rtusim {

class ConfigReader;

// chip.distribution: which unit traces a ray.
enum class RayDistribution {
  kTiles,    // screen tiles of chip.tile_pixels x chip.tile_pixels, dealt round-robin in
             // row-major tile order; a unit traces its pixels' whole ray trees (the GPU way)
  kBatches,  // the frame's rays, in the tracer's order, cut into runs of chip.batch_rays,
             // dealt round-robin
};

struct ChipParams {
  uint32_t units = 1;  // chip.units
  RayDistribution distribution = RayDistribution::kTiles;
  uint32_t tile_pixels = 8;  // chip.tile_pixels: a tile's side
  uint32_t batch_rays = 64;  // chip.batch_rays
  // l2.*: the L2 shared by every unit's caches (all streams); nullopt: l2.enable = false, the
  // units' caches read DRAM directly.
  std::optional<CacheParams> l2;

  // One unit and no L2: the traversal unit straight in front of DRAM, as the tiers model it
  // without a chip.
  bool single_unit() const { return units == 1 && !l2; }
};

// Reads chip.* and l2.* (errors name the key and where it was set).
ChipParams read_chip_params(ConfigReader& r);

}  // namespace rtusim
