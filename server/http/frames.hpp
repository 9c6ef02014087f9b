#pragma once
// Frames of a live session from the overview cameras: the map's walls, the people and the robots as
// boxes, rendered off-screen (render::BoxRenderer) from a snapshot of the session, never inside its
// step.
#include <string>
#include <vector>

#include "render/box_renderer.hpp"

namespace hrisim::sim {
class Session;
}

namespace hrisim::http {

/// Image sizes accepted for frames, pixels.
inline constexpr int kMaxFrameSize = 2048;

/// The session as boxes: floor, walls (the map's outline), people (by their kind's size) and robots
/// (their footprint and height). Ids: 1 the floor, 2 the walls, 100 + agent index for agents.
std::vector<render::Box> scene_of(const sim::Session& session);

/// "overview": straight down onto the whole map, map x up in the image; "follow": behind and above the
/// scenario's first robot, looking where it looks. Throws core::Error (404 unknown camera, 409 follow
/// without a robot).
render::Camera overview_camera(const sim::Session& session, const std::string& name, int width, int height);

/// Renders on this thread's own OSMesa context for that size (kept for the next frame; a thread keeps
/// a few sizes).
render::Frame render_frame(const std::vector<render::Box>& boxes, const render::Camera& camera);

}  // namespace hrisim::http
