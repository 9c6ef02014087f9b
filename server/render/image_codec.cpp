#include "render/image_codec.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "core/error.hpp"

namespace hrisim::render {

std::string encode_png(const ImageRgba8& image) {
  const cv::Mat rgba(image.height, image.width, CV_8UC4, const_cast<std::uint8_t*>(image.pixels.data()));
  cv::Mat bgra;
  cv::cvtColor(rgba, bgra, cv::COLOR_RGBA2BGRA);
  std::vector<std::uint8_t> bytes;
  if (!cv::imencode(".png", bgra, bytes)) throw core::Error(core::ErrorCode::internal, "PNG encoding failed");
  return std::string(bytes.begin(), bytes.end());
}

ImageRgba8 decode_png(std::string_view bytes) {
  const cv::Mat encoded(1, static_cast<int>(bytes.size()), CV_8UC1, const_cast<char*>(bytes.data()));
  const cv::Mat decoded = bytes.empty() ? cv::Mat() : cv::imdecode(encoded, cv::IMREAD_UNCHANGED);
  if (decoded.empty() || decoded.depth() != CV_8U) {
    throw core::Error(core::ErrorCode::bad_request, "not an 8-bit PNG image", {{"bytes", bytes.size()}});
  }
  static const std::map<int, int> kToRgba = {
      {1, cv::COLOR_GRAY2RGBA}, {3, cv::COLOR_BGR2RGBA}, {4, cv::COLOR_BGRA2RGBA}};
  const auto conversion = kToRgba.find(decoded.channels());
  if (conversion == kToRgba.end()) {
    throw core::Error(core::ErrorCode::bad_request, "unsupported PNG colour type",
                      {{"channels", decoded.channels()}});
  }
  cv::Mat rgba;
  cv::cvtColor(decoded, rgba, conversion->second);
  ImageRgba8 image{rgba.cols, rgba.rows, {}};
  image.pixels.assign(rgba.data, rgba.data + rgba.total() * 4);
  return image;
}

std::string encode_jpeg(const ImageRgba8& image, int quality) {
  const cv::Mat rgba(image.height, image.width, CV_8UC4, const_cast<std::uint8_t*>(image.pixels.data()));
  cv::Mat bgr;
  cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
  std::vector<std::uint8_t> bytes;
  if (!cv::imencode(".jpg", bgr, bytes, {cv::IMWRITE_JPEG_QUALITY, quality})) throw core::Error(core::ErrorCode::internal, "JPEG encoding failed");
  return std::string(bytes.begin(), bytes.end());
}

std::string encode_depth16(const std::vector<float>& depth, int width, int height) {
  cv::Mat millimetres(height, width, CV_16UC1);
  for (int y = 0; y < height; ++y) {
    auto* row = millimetres.ptr<std::uint16_t>(y);
    for (int x = 0; x < width; ++x) {
      const double mm = std::round(1000.0 * depth[static_cast<std::size_t>(y) * width + x]);
      row[x] = static_cast<std::uint16_t>(std::clamp(mm, 0.0, 65535.0));
    }
  }
  std::vector<std::uint8_t> bytes;
  if (!cv::imencode(".png", millimetres, bytes)) throw core::Error(core::ErrorCode::internal, "PNG encoding failed");
  return std::string(bytes.begin(), bytes.end());
}

std::vector<std::uint16_t> decode_depth16(std::string_view bytes, int& width, int& height) {
  const cv::Mat encoded(1, static_cast<int>(bytes.size()), CV_8UC1, const_cast<char*>(bytes.data()));
  const cv::Mat decoded = bytes.empty() ? cv::Mat() : cv::imdecode(encoded, cv::IMREAD_UNCHANGED);
  if (decoded.empty() || decoded.type() != CV_16UC1) throw core::Error(core::ErrorCode::bad_request, "not a 16-bit greyscale PNG");
  width = decoded.cols;
  height = decoded.rows;
  std::vector<std::uint16_t> values(decoded.total());
  for (int y = 0; y < height; ++y) std::copy_n(decoded.ptr<std::uint16_t>(y), width, values.data() + static_cast<std::size_t>(y) * width);
  return values;
}

std::string encode_npy(const void* data, std::size_t bytes, std::string_view descr, const std::vector<int>& shape) {
  std::string dims;
  for (const int d : shape) dims += (dims.empty() ? "" : ", ") + std::to_string(d);
  if (shape.size() == 1) dims += ',';  // a Python one-tuple
  std::string header = "{'descr': '" + std::string(descr) + "', 'fortran_order': False, 'shape': (" + dims + "), }";
  // Magic, version, header length, header: the data starts on a 64-byte boundary.
  const std::size_t unpadded = 10 + header.size() + 1;
  header.append((64 - unpadded % 64) % 64, ' ');
  header += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  out += static_cast<char>(header.size() & 0xFF);
  out += static_cast<char>((header.size() >> 8) & 0xFF);
  out += header;
  out.append(static_cast<const char*>(data), bytes);
  return out;
}

std::string opencv_version() { return cv::getVersionString(); }

}  // namespace hrisim::render
