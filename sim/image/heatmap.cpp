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

// A 3x5 pixel font for the scale's labels: five rows of three bits (the top bit is the left).
const uint8_t* glyph(char c) {
  static constexpr struct {
    char c;
    uint8_t rows[5];
  } kFont[] = {
      {'0', {7, 5, 5, 5, 7}}, {'1', {2, 6, 2, 2, 7}}, {'2', {7, 1, 7, 4, 7}},
      {'3', {7, 1, 7, 1, 7}}, {'4', {5, 5, 7, 1, 1}}, {'5', {7, 4, 7, 1, 7}},
      {'6', {7, 4, 7, 5, 7}}, {'7', {7, 1, 1, 1, 1}}, {'8', {7, 5, 7, 5, 7}},
      {'9', {7, 5, 7, 1, 7}}, {'A', {2, 5, 7, 5, 5}}, {'B', {6, 5, 6, 5, 6}},
      {'C', {3, 4, 4, 4, 3}}, {'D', {6, 5, 5, 5, 6}}, {'E', {7, 4, 6, 4, 7}},
      {'G', {3, 4, 5, 5, 3}}, {'I', {7, 2, 2, 2, 7}}, {'K', {5, 5, 6, 5, 5}},
      {'L', {4, 4, 4, 4, 7}}, {'M', {5, 7, 7, 5, 5}}, {'O', {2, 5, 5, 5, 2}},
      {'P', {6, 5, 6, 4, 4}}, {'R', {6, 5, 6, 5, 5}}, {'S', {3, 4, 2, 1, 6}},
      {'T', {7, 2, 2, 2, 2}}, {'X', {5, 5, 2, 5, 5}}, {'Y', {5, 5, 2, 2, 2}},
      {',', {0, 0, 0, 2, 4}}, {' ', {0, 0, 0, 0, 0}}};
  for (const auto& g : kFont)
    if (g.c == c) return g.rows;
  return kFont[sizeof(kFont) / sizeof(kFont[0]) - 1].rows;
}

// Draws `text` with its top-left corner at (x, y), each font pixel `scale` pixels wide.
void draw_text(Rgb8Image& img, int x, int y, const std::string& text, int scale) {
  for (const char c : text) {
    const uint8_t* rows = glyph(c);
    for (int r = 0; r < 5; ++r)
      for (int col = 0; col < 3; ++col) {
        if (!((rows[r] >> (2 - col)) & 1)) continue;
        for (int dy = 0; dy < scale; ++dy)
          for (int dx = 0; dx < scale; ++dx) {
            const int px = x + col * scale + dx, py = y + r * scale + dy;
            if (px < 0 || py < 0 || px >= img.width || py >= img.height) continue;
            unsigned char* p = &img.rgb[(size_t(py) * img.width + px) * 3];
            p[0] = p[1] = p[2] = 255;
          }
      }
    x += 4 * scale;
  }
}

int text_width(const std::string& text, int scale) { return int(text.size()) * 4 * scale - scale; }

// "1 B", "10 KB", ...: 10^exponent bytes in decimal units.
std::string bytes_label(int exponent) {
  static const char* const kUnits[] = {"B", "KB", "MB", "GB", "TB"};
  std::string digits = "1";
  for (int i = 0; i < exponent % 3; ++i) digits += '0';
  return digits + " " + kUnits[std::min(exponent / 3, 4)];
}

}  // namespace

Rgb8Image heatmap_with_scale_rgb8(const std::vector<uint64_t>& bytes, int width, int height,
                                  uint64_t max_bytes) {
  const int scale = width >= 384 ? 2 : 1;
  const int margin = 6 * scale, bar_h = 6 * scale, tick_h = 2 * scale, glyph_h = 5 * scale;
  const int strip = margin + bar_h + tick_h + 2 * scale + glyph_h + 3 * scale + glyph_h + margin;
  Rgb8Image img{width, height + strip, heatmap_rgb8(bytes, max_bytes)};
  img.rgb.resize(size_t(img.width) * img.height * 3, 0);  // the strip starts black
  const int x0 = margin, x1 = std::max(x0 + 1, width - margin);
  const double top = std::log1p(static_cast<double>(std::max<uint64_t>(1, max_bytes)));
  // The gradient, on the same log scale as the map.
  const int bar_y = height + margin;
  for (int x = x0; x < x1; ++x) {
    unsigned char rgb[3];
    scale_colour(double(x - x0) / double(x1 - 1 - x0 > 0 ? x1 - 1 - x0 : 1), rgb);
    for (int y = bar_y; y < bar_y + bar_h; ++y)
      std::copy(rgb, rgb + 3, &img.rgb[(size_t(y) * width + x) * 3]);
  }
  // Ticks and labels at powers of ten bytes that fit without overlapping.
  const int label_y = bar_y + bar_h + tick_h + 2 * scale;
  int free_from = 0;
  for (int e = 0; std::pow(10.0, e) <= double(std::max<uint64_t>(1, max_bytes)); ++e) {
    const double at = std::log1p(std::pow(10.0, e)) / top;
    const int x = x0 + int(std::lround(at * (x1 - 1 - x0)));
    for (int y = bar_y + bar_h; y < bar_y + bar_h + tick_h; ++y)
      for (int dx = 0; dx < scale && x + dx < width; ++dx) {
        unsigned char* p = &img.rgb[(size_t(y) * width + x + dx) * 3];
        p[0] = p[1] = p[2] = 255;
      }
    const std::string label = bytes_label(e);
    const int lx = std::clamp(x - text_width(label, scale) / 2, 0, std::max(0, width - text_width(label, scale)));
    if (lx < free_from) continue;
    draw_text(img, lx, label_y, label, scale);
    free_from = lx + text_width(label, scale) + 3 * scale;
  }
  const std::string caption = width >= 130 * scale ? "DRAM BYTES PER PIXEL, LOG SCALE" : "BYTES PER PIXEL";
  draw_text(img, x0, label_y + glyph_h + 3 * scale, caption, scale);
  return img;
}

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
