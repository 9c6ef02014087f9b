#pragma once
// JSON views of a live session (its lock held by the caller): status, state, sensors, poses, spaces,
// Gymnasium's observation, snapshots, and the binary laser and camera frames.
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/json_writer.hpp"
#include "episode/episode.hpp"
#include "http/session_work.hpp"
#include "runs/event_json.hpp"
#include "sim/camera_scene.hpp"
#include "sim/session.hpp"
#include "tasks/task.hpp"

namespace hrisim::http {

/// Most state frames per second a WebSocket subscription may ask for.
inline constexpr double kMaxPushRate = 60.0;

/// The session's scene as a binary scene frame (scene_message): what moves, or with `all` everything.
Response scene_frame(const sim::Session& session, bool all);

using runs::event_json;
/// What each instance id of sim::scene_of stands for: [{"id", "kind" (floor, walls, obstacle, door,
/// object, human, robot, robot_link), "name", and "agent"/"link" where they apply}].
nlohmann::json segmentation_legend(const sim::Session& session);
/// Status of a session: id, scenario, seed, mode, tick, time, its end, the choreography step, the task,
/// the state hash; as members of an object being written, or as a JSON object.
void write_status(core::JsonWriter& out, const LiveSession& live);
nlohmann::json status_of(const LiveSession& live);
/// Every metric of the episode computed from its recording so far (null, with its reason, where one
/// cannot be yet), with the tick and time: on the worker pool, as a long session has many steps.
nlohmann::json metrics_so_far(const LiveSession& live);
/// Every agent's pose and motion, requests waiting for an answer, and the events since a tick.
nlohmann::json state_of(const LiveSession& live, std::int64_t events_since_tick);
/// A pose as x, y, z, roll, pitch, yaw (rpy about fixed x, y, z).
nlohmann::json pose_json(const Eigen::Isometry3d& pose);
/// A number as JSON, infinities spelled "inf" and "-inf", which JSON numbers cannot hold (REP 117's
/// out-of-range laser values, unbounded Box spaces).
nlohmann::json number_or_infinity(double value);
/// A Gymnasium space in gym-http-api's form: {"name": "Box", shape, low, high, dtype} or {"name": "Discrete", n}.
/// low and high hold one value per element, or one for all of them. An image observation names its
/// camera: the observation is that camera's frame, not in the step's JSON.
nlohmann::json space_json(const tasks::Space& space, const std::optional<tasks::ImageObservation>& image = std::nullopt);
/// A robot's latest sensor readings and its joints.
nlohmann::json sensors_of(const sim::Session& session, const std::string& name);
/// Every agent's and movable object's pose.
nlohmann::json poses_of(const sim::Session& session);
/// Gymnasium's observation and info now: the observation null when it is a camera image (fetched as
/// a binary camera frame), info the tick, time and the last step's reward terms; as members of an
/// object being written, or added to a JSON object.
void write_observation(core::JsonWriter& out, const LiveSession& live);
void add_observation(const LiveSession& live, nlohmann::json& reply);
nlohmann::json snapshot_json(const std::string& id, const episode::Episode::Snapshot& snapshot);
/// A robot's laser reading by sensor name (the first laser when empty), as a binary frame.
std::string laser_of(const sim::Session& session, const std::string& robot, const std::string& sensor);
/// A listening robot's last tick of audio as a binary frame: a 48-byte little-endian header "HRAU"
/// (version, header size, tick, time, first sample, sample rate, channels, samples per channel), then
/// float32 sound pressure in Pa, channel after channel (api/asyncapi.yaml, docs/sound.md).
std::string audio_of(const sim::Session& session, const std::string& robot);
/// A camera's name, kind, image size, intrinsics, range, rate and pose (position and quaternion x, y, z, w).
nlohmann::json camera_json(const sim::CameraInfo& info);
/// A binary RGB-D frame of a camera, as a deferred answer: the scene is taken now (the caller holds
/// the session's lock), the worker pool draws it.
Response camera_frame(const sim::Session& session, const std::string& name, int width, int height, bool ids);
/// A camera's frame (colour, depth, ids) as work for the worker pool: the scene is taken now (the caller
/// holds the session's lock), the work draws it. Throws core::Error(not_found) for no such camera.
std::function<render::Frame()> draw_later(const sim::Session& session, const std::string& name, int width, int height);

}  // namespace hrisim::http
