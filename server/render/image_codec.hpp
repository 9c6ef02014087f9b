#pragma once
// Image encodings (OpenCV's imgcodecs): PNG and JPEG of colour, 16-bit PNG of depth in millimetres
// (ROS's 16UC1 convention), and NumPy's .npy for arrays a Python client loads without decoding.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "render/image.hpp"

namespace hrisim::render {

/// Lossless PNG with alpha.
std::string encode_png(const ImageRgba8& image);
/// Decodes a PNG (any colour type) to RGBA; throws core::Error(bad_request) when it is not one.
ImageRgba8 decode_png(std::string_view bytes);
/// JPEG of the colour (alpha dropped), quality 0–100.
std::string encode_jpeg(const ImageRgba8& image, int quality = 90);
/// A 16-bit greyscale PNG of depth in millimetres (rounded, capped at 65535); 0 where nothing is.
std::string encode_depth16(const std::vector<float>& depth, int width, int height);
/// Reads a 16-bit greyscale PNG back (row-major, top row first); throws core::Error(bad_request).
std::vector<std::uint16_t> decode_depth16(std::string_view bytes, int& width, int& height);
/// A NumPy .npy file (format 1.0, little-endian, C order) holding `data` with `shape`; `descr` is
/// NumPy's type string, e.g. "<f4", "|u1", "<u4".
std::string encode_npy(const void* data, std::size_t bytes, std::string_view descr, const std::vector<int>& shape);
/// Version of the OpenCV library in use, e.g. "4.6.0".
std::string opencv_version();

}  // namespace hrisim::render
