#pragma once
// PNG encoding and decoding of RGBA images (OpenCV's imgcodecs).
#include <string>
#include <string_view>

#include "render/image.hpp"

namespace hrisim::render {

/// Lossless PNG with alpha.
std::string encode_png(const ImageRgba8& image);
/// Decodes a PNG (any colour type) to RGBA; throws core::Error(bad_request) when it is not one.
ImageRgba8 decode_png(std::string_view bytes);
/// Version of the OpenCV library in use, e.g. "4.6.0".
std::string opencv_version();

}  // namespace hrisim::render
