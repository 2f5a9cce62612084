#pragma once
// Writes RGB pixels as a PNG with libpng (8-bit RGB, no row filter, deflate-compressed).
#include <cstdint>
#include <string>
#include <vector>

namespace dynweigh::tools {

// `rgb` holds height rows of width x 3 bytes, top row first. Throws std::runtime_error on a
// write error.
void write_png(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb);

}  // namespace dynweigh::tools
