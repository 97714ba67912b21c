// Per-pixel traffic pictures: a heatmap of bytes, and a signed difference map of two layouts.
#pragma once
#include <cstdint>
#include <vector>

namespace rtusim {

// Log-scaled heatmap (black -> purple -> orange -> yellow) of `bytes`, with `max_bytes` at the
// top of the scale (pass the maximum over every map to compare them).
std::vector<unsigned char> heatmap_rgb8(const std::vector<uint64_t>& bytes, uint64_t max_bytes);

// Difference map of b - a per pixel: blue where b moves fewer bytes, red where more, white
// equal; full saturation at the largest absolute difference.
std::vector<unsigned char> difference_rgb8(const std::vector<uint64_t>& a,
                                           const std::vector<uint64_t>& b);

}  // namespace rtusim
