#pragma once
// Writes frames to a video file through OpenCV's videoio: H.264 in .mp4 (MPEG-4 part 2 where FFmpeg has
// no H.264 encoder), VP8 in .webm, Motion JPEG in .avi.
#include <filesystem>
#include <memory>
#include <string>

#include "render/image.hpp"

namespace hrisim::render {

class VideoWriter {
 public:
  /// Opens `path` for frames of width × height at `fps`; the codec follows the extension (.mp4,
  /// .webm or .avi). Throws core::Error(bad_request) for another extension, internal when it cannot be opened.
  VideoWriter(const std::filesystem::path& path, double fps, int width, int height);
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  void write(const ImageRgba8& frame);
  /// Finishes the file (also done by the destructor).
  void close();
  int frames() const { return frames_; }
  /// h264, mpeg4, vp8 or mjpeg.
  const std::string& codec() const { return codec_; }

 private:
  struct Cv;
  std::unique_ptr<Cv> cv_;
  int frames_ = 0;
  std::string codec_;
};

}  // namespace hrisim::render
