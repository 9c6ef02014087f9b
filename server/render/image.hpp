#pragma once
// An 8-bit RGBA image in memory, rows top to bottom, the unit renderers produce and codecs encode.
#include <cstdint>
#include <vector>

namespace hrisim::render {

struct ImageRgba8 {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  ///< width × height × 4 bytes, row 0 at the top

  const std::uint8_t* pixel(int x, int y) const { return pixels.data() + 4 * (static_cast<std::size_t>(y) * width + x); }
};

}  // namespace hrisim::render
