// Deals the frame's rays to the chip's units (chip.distribution): by the screen tile of the ray's
// pixel, or in runs of consecutive rays. Ask for each ray in the tracer's order: the batches
// distribution counts them. And the order of the frame's pixels on a chip.
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

#include "chip/chip_params.h"

namespace rtusim {

// The order a chip traces the frame's pixels in: with chip.distribution = tiles, tile by tile
// (tiles row by row, each tile's pixels row by row), so each unit traces its tiles one after
// another; empty (the tracer's scan order) for the batches distribution and for one unit
// without an L2.
inline std::vector<uint32_t> chip_pixel_order(const ChipParams& chip, uint32_t width,
                                              uint32_t height) {
  std::vector<uint32_t> order;
  if (chip.single_unit() || chip.distribution != RayDistribution::kTiles) return order;
  order.reserve(uint64_t{width} * height);
  const uint32_t t = chip.tile_pixels;
  for (uint32_t ty = 0; ty < height; ty += t)
    for (uint32_t tx = 0; tx < width; tx += t)
      for (uint32_t y = ty; y < std::min(height, ty + t); ++y)
        for (uint32_t x = tx; x < std::min(width, tx + t); ++x) order.push_back(y * width + x);
  return order;
}

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
