// An 8-bit RGB picture and its PNG file (libpng).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ovpc::sim {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< row-major, top row first, 3 bytes per pixel

  const std::uint8_t* Pixel(int x, int y) const {
    return rgb.data() + 3 * (static_cast<std::size_t>(y) * width + x);
  }
};

/// Writes `image` as an 8-bit RGB PNG.
/// @throws std::invalid_argument if the image is inconsistent, std::runtime_error if the file
/// cannot be written.
void WritePng(const Image& image, const std::string& path);

}  // namespace ovpc::sim
