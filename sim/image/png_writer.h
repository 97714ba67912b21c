// PNG output of linear-RGB frames (clamped, sRGB-encoded, 8 bits per channel).
#pragma once
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace rtusim {

// Encodes linear RGB to 8-bit sRGB, row-major, y = 0 the top row.
std::vector<unsigned char> to_srgb8(const std::vector<glm::vec3>& linear);
// Writes 8-bit RGB pixels as PNG; throws std::runtime_error on failure.
void write_png(const std::string& path, int width, int height,
               const std::vector<unsigned char>& rgb8);

}  // namespace rtusim
