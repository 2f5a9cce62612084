#pragma once
// Writes RGB pixels as a PNG without a library: stored (uncompressed) deflate blocks are valid
// PNG, and a screenshot for a test or a README needs nothing more.
#include <cstdint>
#include <string>
#include <vector>

namespace dynweigh::tools {

// `rgb` holds height rows of width x 3 bytes, top row first. Throws std::runtime_error on a
// write error.
void write_png(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb);

}  // namespace dynweigh::tools
