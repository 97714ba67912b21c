// PNG output through stb_image_write (Debian's libstb).
#include "image/png_writer.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <stb_image_write.h>

#include "util/error.h"

namespace rtusim {

std::vector<unsigned char> to_srgb8(const std::vector<glm::vec3>& linear) {
  std::vector<unsigned char> out(linear.size() * 3);
  for (size_t i = 0; i < linear.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const float v = linear[i][c];
      const float x = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
      const float s = x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
      out[i * 3 + c] = static_cast<unsigned char>(std::lround(s * 255.0f));
    }
  return out;
}

void write_png(const std::string& path, int width, int height,
               const std::vector<unsigned char>& rgb8) {
  if (!stbi_write_png(path.c_str(), width, height, 3, rgb8.data(), width * 3))
    throw InputError(path + ": cannot write PNG (" + std::strerror(errno) + ")");
}

}  // namespace rtusim
