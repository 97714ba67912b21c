// Per-pixel traffic pictures: a heatmap of bytes, and a signed difference map of two layouts.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace rtusim {

// Log-scaled heatmap (black -> purple -> orange -> yellow) of `bytes`, with `max_bytes` at the
// top of the scale (pass the maximum over every map to compare them).
std::vector<unsigned char> heatmap_rgb8(const std::vector<uint64_t>& bytes, uint64_t max_bytes);

// An RGB8 picture with its size.
struct Rgb8Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
};

// The heatmap of a width x height frame with its colour scale below it: the gradient, ticks at
// powers of ten bytes labelled in B, KB, MB, GB (decimal), and the caption "DRAM BYTES PER
// PIXEL, LOG SCALE" (a built-in 3x5 pixel font, scaled with the frame).
Rgb8Image heatmap_with_scale_rgb8(const std::vector<uint64_t>& bytes, int width, int height,
                                  uint64_t max_bytes);

// Difference map of b - a per pixel: blue where b moves fewer bytes, red where more, white
// equal; full saturation at the largest absolute difference.
std::vector<unsigned char> difference_rgb8(const std::vector<uint64_t>& a,
                                           const std::vector<uint64_t>& b);

}  // namespace rtusim
