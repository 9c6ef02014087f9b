#pragma once
// Camera frames of a live session: which image in which format a request asks for, encoding it, and
// the binary WebSocket layout of an RGB-D frame. The scene is taken from the session under its lock
// (sim::scene_of) and drawn afterwards on a worker thread's own OSMesa context, never inside a step.
#include <cstdint>
#include <string>

#include "http/router.hpp"
#include "render/scene_renderer.hpp"

namespace hrisim::sim {
struct CameraInfo;
}

namespace hrisim::http {

/// Image sizes accepted for frames, pixels.
inline constexpr int kMaxFrameSize = 2048;

/// What a frame request asks for: ?format=png|jpeg|depth16|npy, ?image=colour|depth|segmentation,
/// ?width=&height= (the camera's own size when absent).
struct FrameRequest {
  enum class Image { colour, depth, segmentation };
  std::string format = "png";
  Image image = Image::colour;
  int width = 0, height = 0;  ///< 0: the camera's own
};

/// Reads and checks the query; throws core::Error(bad_request) naming the parameter.
FrameRequest frame_request(const Request& request);

/// The frame as the request asked: content type and bytes.
Response encode_frame(const render::Frame& frame, const FrameRequest& request);

/// The camera's RGB-D frame of the scene, drawn on this thread, as a binary WebSocket message: a
/// 96-byte little-endian header "HRCF", then RGBA8, depth float32 (m) and, when asked, instance ids
/// uint32, each row-major from the top row. Layout in api/asyncapi.yaml. The images are read back
/// straight into the message.
std::string camera_message(const render::Scene& scene, const sim::CameraInfo& camera, std::int64_t tick, double time, bool with_ids);

/// Bytes of a scene frame's header and of each of its parts.
inline constexpr std::size_t kSceneHeaderBytes = 32;
inline constexpr std::size_t kScenePartBytes = 48;

/// What moves in a scene (doors, movable objects, people's body capsules, robots' links; `all`: the
/// floor, walls and furniture too, meshes as their bounding boxes) as a binary message a browser draws
/// in 3D: a 32-byte little-endian header "HRSF", then 48 bytes a part. Layout in api/asyncapi.yaml.
std::string scene_message(const render::Scene& scene, std::int64_t tick, double time, bool all);

}  // namespace hrisim::http
