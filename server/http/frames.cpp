#include "http/frames.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <vector>

#include "core/error.hpp"
#include "http/request_helpers.hpp"
#include "render/image_codec.hpp"
#include "sim/camera_scene.hpp"

namespace hrisim::http {

FrameRequest frame_request(const Request& request) {
  FrameRequest asked;
  asked.format = query_value(request.query, "format").value_or("png");
  if (asked.format != "png" && asked.format != "jpeg" && asked.format != "depth16" && asked.format != "npy") {
    throw core::Error(core::ErrorCode::bad_request, "format: png, jpeg, depth16 or npy", {{"parameter", "format"}});
  }
  const std::string image = query_value(request.query, "image").value_or(asked.format == "depth16" ? "depth" : "colour");
  if (image == "colour") {
    asked.image = FrameRequest::Image::colour;
  } else if (image == "depth") {
    asked.image = FrameRequest::Image::depth;
  } else if (image == "segmentation") {
    asked.image = FrameRequest::Image::segmentation;
  } else {
    throw core::Error(core::ErrorCode::bad_request, "image: colour, depth or segmentation", {{"parameter", "image"}});
  }
  // Which formats carry which image.
  const bool fits = asked.format == "npy" || (asked.image == FrameRequest::Image::colour && (asked.format == "png" || asked.format == "jpeg")) ||
                    (asked.image == FrameRequest::Image::depth && asked.format == "depth16") ||
                    (asked.image == FrameRequest::Image::segmentation && asked.format == "png");
  if (!fits) {
    throw core::Error(core::ErrorCode::bad_request,
                      "format " + asked.format + " does not carry the " + image + " image (colour: png, jpeg, npy; depth: depth16, npy; segmentation: png, npy)",
                      {{"parameter", "format"}});
  }
  asked.width = static_cast<int>(integer_query(request, "width", 16, kMaxFrameSize, 0));
  asked.height = static_cast<int>(integer_query(request, "height", 16, kMaxFrameSize, 0));
  return asked;
}

Response encode_frame(const render::Frame& frame, const FrameRequest& request) {
  const int w = frame.colour.width, h = frame.colour.height;
  switch (request.image) {
    case FrameRequest::Image::colour:
      if (request.format == "jpeg") return Response{200, "image/jpeg", render::encode_jpeg(frame.colour), {}, {}};
      if (request.format == "npy") {
        return Response{200, "application/octet-stream", render::encode_npy(frame.colour.pixels.data(), frame.colour.pixels.size(), "|u1", {h, w, 4}), {}, {}};
      }
      return Response{200, "image/png", render::encode_png(frame.colour), {}, {}};
    case FrameRequest::Image::depth:
      if (request.format == "npy") {
        return Response{200, "application/octet-stream", render::encode_npy(frame.depth.data(), frame.depth.size() * sizeof(float), "<f4", {h, w}), {}, {}};
      }
      return Response{200, "image/png", render::encode_depth16(frame.depth, w, h), {}, {}};
    case FrameRequest::Image::segmentation: {
      if (request.format == "npy") {
        return Response{200, "application/octet-stream", render::encode_npy(frame.ids.data(), frame.ids.size() * sizeof(std::uint32_t), "<u4", {h, w}), {}, {}};
      }
      // The id's three low bytes as red, green and blue.
      render::ImageRgba8 ids{w, h, std::vector<std::uint8_t>(frame.ids.size() * 4)};
      for (std::size_t i = 0; i < frame.ids.size(); ++i) {
        ids.pixels[4 * i] = frame.ids[i] & 0xFF;
        ids.pixels[4 * i + 1] = (frame.ids[i] >> 8) & 0xFF;
        ids.pixels[4 * i + 2] = (frame.ids[i] >> 16) & 0xFF;
        ids.pixels[4 * i + 3] = 255;
      }
      return Response{200, "image/png", render::encode_png(ids), {}, {}};
    }
  }
  throw core::Error(core::ErrorCode::internal, "unknown frame image");
}

std::string camera_message(const render::Scene& scene, const sim::CameraInfo& camera, std::int64_t tick, double time, bool with_ids) {
  static_assert(std::endian::native == std::endian::little, "binary frames are written in the host's byte order");
  constexpr std::size_t kHeader = 96, kNameBytes = 36;
  const std::size_t pixels = static_cast<std::size_t>(camera.camera.width) * camera.camera.height;
  std::string out(kHeader + pixels * (4 + 4 + (with_ids ? 4 : 0)), '\0');
  char* data = out.data();
  const auto put = [&](std::size_t offset, auto value) { std::memcpy(data + offset, &value, sizeof value); };
  const render::Camera& c = camera.camera;
  std::memcpy(data, "HRCF", 4);
  put(4, std::uint16_t{1});  // format version
  put(6, static_cast<std::uint16_t>(kHeader));
  put(8, tick);
  put(16, time);
  put(24, static_cast<std::uint32_t>(c.width));
  put(28, static_cast<std::uint32_t>(c.height));
  put(32, static_cast<float>(c.fx));
  put(36, static_cast<float>(c.fy));
  put(40, static_cast<float>(c.cx));
  put(44, static_cast<float>(c.cy));
  put(48, static_cast<float>(c.near));
  put(52, static_cast<float>(c.far));
  put(56, std::uint32_t{with_ids ? 7u : 3u});  // parts: 1 colour, 2 depth, 4 ids
  // Cut at a character boundary: never inside a UTF-8 sequence.
  std::size_t name_bytes = std::min(camera.name.size(), kNameBytes - 1);
  while (name_bytes > 0 && name_bytes < camera.name.size() && (static_cast<unsigned char>(camera.name[name_bytes]) & 0xC0) == 0x80) --name_bytes;
  std::memcpy(data + 60, camera.name.data(), name_bytes);
  // Parts of 4-byte values at 4-byte offsets: the images can be read back in place.
  char* const colour = data + kHeader;
  render::renderer_on_this_thread(c.width, c.height)
      .render_into(scene, c,
                   {reinterpret_cast<std::uint8_t*>(colour), reinterpret_cast<float*>(colour + pixels * 4),
                    with_ids ? reinterpret_cast<std::uint32_t*>(colour + pixels * 8) : nullptr});
  return out;
}

std::string scene_message(const render::Scene& scene, std::int64_t tick, double time, bool all) {
  static_assert(std::endian::native == std::endian::little, "binary frames are written in the host's byte order");
  std::vector<const render::Part*> parts;
  for (const render::Part& part : scene) {
    if (all || part.id >= sim::kDoorIdBase) parts.push_back(&part);
  }
  std::string out(kSceneHeaderBytes + parts.size() * kScenePartBytes, '\0');
  char* data = out.data();
  const auto put = [&](std::size_t offset, auto value) { std::memcpy(data + offset, &value, sizeof value); };
  std::memcpy(data, "HRSF", 4);
  put(4, std::uint16_t{1});  // format version
  put(6, static_cast<std::uint16_t>(kSceneHeaderBytes));
  put(8, tick);
  put(16, time);
  put(24, static_cast<std::uint32_t>(parts.size()));
  put(28, static_cast<std::uint32_t>(kScenePartBytes));
  std::size_t at = kSceneHeaderBytes;
  for (const render::Part* part : parts) {
    const bool capsule = part->shape == render::Part::Shape::capsule;
    // A mesh goes as the box its bounds fill.
    const auto shape = part->shape == render::Part::Shape::mesh ? render::Part::Shape::box : part->shape;
    put(at, part->id);
    put(at + 4, static_cast<std::uint8_t>(shape));
    for (int c = 0; c < 3; ++c) put(at + 5 + c, static_cast<std::uint8_t>(std::lround(std::clamp(part->colour[c], 0.0f, 1.0f) * 255.0f)));
    const Eigen::Vector3d first = capsule ? part->from : part->pose.translation();
    const Eigen::Vector3d second = capsule ? part->to : part->size;
    const Eigen::Quaterniond rotation(part->pose.linear());
    const std::array<double, 4> last = capsule ? std::array<double, 4>{part->radius, 0.0, 0.0, 0.0}
                                               : std::array<double, 4>{rotation.x(), rotation.y(), rotation.z(), rotation.w()};
    for (int i = 0; i < 3; ++i) put(at + 8 + 4 * i, static_cast<float>(first[i]));
    for (int i = 0; i < 3; ++i) put(at + 20 + 4 * i, static_cast<float>(second[i]));
    for (int i = 0; i < 4; ++i) put(at + 32 + 4 * i, static_cast<float>(last[i]));
    at += kScenePartBytes;
  }
  return out;
}

}  // namespace hrisim::http
