#include "render/video_writer.hpp"

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace hrisim::render {

struct VideoWriter::Cv {
  cv::VideoWriter writer;
  cv::Mat bgr;
};

VideoWriter::VideoWriter(const std::filesystem::path& path, double fps, int width, int height) : cv_(std::make_unique<Cv>()) {
  struct Codec {
    const char* name;
    int fourcc;
  };
  // In the order tried: H.264 plays in browsers and players, MPEG-4 part 2 is the fallback of a build
  // without an H.264 encoder.
  std::vector<Codec> codecs;
  const std::string extension = path.extension().string();
  if (extension == ".mp4") {
    codecs = {{"h264", cv::VideoWriter::fourcc('a', 'v', 'c', '1')}, {"mpeg4", cv::VideoWriter::fourcc('m', 'p', '4', 'v')}};
  } else if (extension == ".webm") {
    codecs = {{"vp8", cv::VideoWriter::fourcc('V', 'P', '8', '0')}};
  } else if (extension == ".avi") {
    codecs = {{"mjpeg", cv::VideoWriter::fourcc('M', 'J', 'P', 'G')}};
  } else {
    throw core::Error(core::ErrorCode::bad_request, "video file " + path.string() + ": the name must end in .mp4, .webm or .avi");
  }
  for (const Codec& codec : codecs) {
    if (cv_->writer.open(path.string(), cv::CAP_FFMPEG, codec.fourcc, fps, cv::Size(width, height))) {
      codec_ = codec.name;
      return;
    }
  }
  throw core::Error(core::ErrorCode::internal, "cannot write the video " + path.string() + " (OpenCV's FFmpeg backend refused it)");
}

VideoWriter::~VideoWriter() { close(); }

void VideoWriter::write(const ImageRgba8& frame) {
  const cv::Mat rgba(frame.height, frame.width, CV_8UC4, const_cast<std::uint8_t*>(frame.pixels.data()));
  cv::cvtColor(rgba, cv_->bgr, cv::COLOR_RGBA2BGR);
  cv_->writer.write(cv_->bgr);
  ++frames_;
}

void VideoWriter::close() {
  if (cv_->writer.isOpened()) cv_->writer.release();
}

}  // namespace hrisim::render
