// Deals the frame's rays to the chip's units (chip.distribution): by the screen tile of the ray's
// pixel, or in runs of consecutive rays. Ask for each ray in the tracer's order: the batches
// distribution counts them.
#pragma once
#include <cstdint>

#include "chip/chip_params.h"

namespace rtusim {

class RayDealer {
 public:
  RayDealer(const ChipParams& chip, uint32_t width)
      : units_(chip.units), distribution_(chip.distribution), tile_(chip.tile_pixels),
        tiles_per_row_((width + chip.tile_pixels - 1) / chip.tile_pixels),
        width_(width), batch_rays_(chip.batch_rays) {}

  // The unit that traces the next ray, of `pixel`.
  uint32_t next(uint32_t pixel) {
    if (distribution_ == RayDistribution::kTiles) {
      const uint32_t x = pixel % width_, y = pixel / width_;
      return static_cast<uint32_t>((uint64_t{y / tile_} * tiles_per_row_ + x / tile_) % units_);
    }
    return static_cast<uint32_t>(rays_++ / batch_rays_ % units_);
  }

 private:
  uint32_t units_;
  RayDistribution distribution_;
  uint32_t tile_, tiles_per_row_, width_;
  uint64_t batch_rays_;
  uint64_t rays_ = 0;  // dealt so far (batches)
};

}  // namespace rtusim
