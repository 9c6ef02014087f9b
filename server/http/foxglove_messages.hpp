#pragma once
// A live session's state as Foxglove's well-known messages (foxglove.SceneUpdate, FrameTransforms,
// LaserScan, PosesInFrame, CompressedImage, Log) in their JSON encoding, and the JSON Schemas hrisim
// advertises its channels with. Free of sockets: the Foxglove socket (foxglove_socket.cpp) sends them.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "http/robot_frames.hpp"
#include "render/scene_renderer.hpp"

namespace hrisim::sim {
class Session;
struct LaserReading;
struct PeopleReading;
}  // namespace hrisim::sim

namespace hrisim::http::foxglove {

/// The fixed frame everything is placed in, and a robot's frames under it.
using http::kMapFrame;
using http::base_frame;
using http::sensor_frame;

/// Simulated time as Foxglove's nanoseconds and as its {sec, nsec}.
std::uint64_t nanoseconds(double seconds);
nlohmann::json time_json(double seconds);

/// The scene's solids as entities in the map frame, one per instance id, each replacing the last of
/// its id: the fixed ones (floor, walls, furniture), kept for good, or what moves (doors, objects,
/// people's body capsules as a cylinder and two spheres, robots' links) with the paths people and robots
/// walk (from where they stand through the path's points left), each kept `lifetime` seconds of
/// simulated time unless sent again (so that someone who left, or a path walked, goes).
nlohmann::json scene_update(const render::Scene& scene, const sim::Session& session, bool fixed, double lifetime = 0.0);
/// map → ROBOT/base_link for every robot with a model, and ROBOT/base_link → ROBOT/SENSOR for each
/// sensor of its description.
nlohmann::json frame_transforms(const sim::Session& session);
/// A laser's reading in the map frame at the pose it was taken from; a beam with no return (REP 117's
/// infinities, which JSON cannot hold) is 0.
nlohmann::json laser_scan(const sim::LaserReading& reading, double dt);
/// The people detector's detections as positions in the map frame, heading along their velocity.
nlohmann::json people_poses(const sim::PeopleReading& reading, double dt);
nlohmann::json compressed_image(const std::string& bytes, const std::string& format, const std::string& frame, double time);
/// A depth image as Foxglove's RawImage: 32FC1, metres along the optical axis, 0 where nothing is.
nlohmann::json depth_image(const std::vector<float>& depth, int width, int height, const std::string& frame, double time);
/// An event (runs::event_json's shape) as a log line: its subject as the name, its kind and data as
/// the message.
nlohmann::json log_line(const nlohmann::json& event);

/// The JSON Schema (json text) hrisim advertises a message with, by schema name: the Foxglove schemas
/// above, hrisim.Metrics, and the services' requests and responses; throws core::Error(internal) for
/// another name.
const std::string& schema_text(const std::string& schema_name);

}  // namespace hrisim::http::foxglove
