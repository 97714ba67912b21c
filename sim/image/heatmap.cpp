// Heatmap and difference-map colouring.
#include "image/heatmap.h"

#include <algorithm>
#include <cmath>

namespace rtusim {
namespace {

// A few stops of an inferno-like scale, interpolated linearly.
void scale_colour(double x, unsigned char* rgb) {
  static constexpr double kStops[][3] = {{0, 0, 4},       {40, 11, 84},   {101, 21, 110},
                                         {159, 42, 99},   {212, 72, 66},  {245, 125, 21},
                                         {250, 193, 39},  {252, 255, 164}};
  constexpr int n = sizeof(kStops) / sizeof(kStops[0]);
  x = std::clamp(x, 0.0, 1.0) * (n - 1);
  const int i = std::min(static_cast<int>(x), n - 2);
  const double f = x - i;
  for (int c = 0; c < 3; ++c)
    rgb[c] = static_cast<unsigned char>(std::lround(kStops[i][c] * (1 - f) + kStops[i + 1][c] * f));
}

}  // namespace

std::vector<unsigned char> heatmap_rgb8(const std::vector<uint64_t>& bytes, uint64_t max_bytes) {
  std::vector<unsigned char> out(bytes.size() * 3);
  const double top = std::log1p(static_cast<double>(std::max<uint64_t>(1, max_bytes)));
  for (size_t i = 0; i < bytes.size(); ++i)
    scale_colour(std::log1p(static_cast<double>(bytes[i])) / top, &out[i * 3]);
  return out;
}

std::vector<unsigned char> difference_rgb8(const std::vector<uint64_t>& a,
                                           const std::vector<uint64_t>& b) {
  double max_abs = 1.0;
  for (size_t i = 0; i < a.size(); ++i)
    max_abs = std::max(max_abs, std::abs(double(b[i]) - double(a[i])));
  std::vector<unsigned char> out(a.size() * 3);
  for (size_t i = 0; i < a.size(); ++i) {
    const double d = (double(b[i]) - double(a[i])) / max_abs;  // -1 .. 1
    const double fade = 1.0 - std::sqrt(std::abs(d));           // 1 = white
    const auto c = static_cast<unsigned char>(std::lround(255.0 * fade));
    out[i * 3 + 0] = d > 0 ? 255 : c;
    out[i * 3 + 1] = c;
    out[i * 3 + 2] = d < 0 ? 255 : c;
  }
  return out;
}

}  // namespace rtusim
