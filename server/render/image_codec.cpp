#include "render/image_codec.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <map>

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

std::string opencv_version() { return cv::getVersionString(); }

}  // namespace hrisim::render
