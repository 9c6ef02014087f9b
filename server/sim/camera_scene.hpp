#pragma once
// What cameras see of a session: its state as solids for the renderer (floor, walls, furniture meshes,
// doors as they stand, people's animated bodies, robots' links where their joints put them, movable
// objects), and the session's cameras — the robots' own from their descriptions, a top-down
// orthographic overview of the whole map and a perspective camera following the robot. Built from
// the session under its lock (cheap); drawing happens afterwards, off the simulation step.
#include <cstdint>
#include <string>
#include <vector>

#include "render/scene_renderer.hpp"

namespace hrisim::sim {

class Session;

// Instance ids in segmentation images (0 is nothing).
inline constexpr std::uint32_t kFloorId = 1;
inline constexpr std::uint32_t kWallsId = 2;            ///< the map's outline (a map from an image)
inline constexpr std::uint32_t kObstacleIdBase = 1000;  ///< + obstacle index (walls and furniture)
inline constexpr std::uint32_t kDoorIdBase = 2000;      ///< + door index
inline constexpr std::uint32_t kObjectIdBase = 3000;    ///< + movable object index
inline constexpr std::uint32_t kAgentIdBase = 10000;    ///< + agent index: a person, or a robot without a model
inline constexpr std::uint32_t kRobotLinkIdBase = 1000000;  ///< + agent index × 1000 + link index
/// Height of walls drawn for a map from an image, m.
inline constexpr double kDrawnWallHeight = 2.5;
/// Height of a door leaf, m.
inline constexpr double kDoorHeight = 2.1;

/// The session as the renderer's solids.
render::Scene scene_of(const Session& session);

/// A camera the session offers.
struct CameraInfo {
  std::string name;   ///< "overview", "follow", or ROBOT.SENSOR
  std::string kind;   ///< "orthographic", "perspective", or the sensor's type (camera, rgbd_camera)
  render::Camera camera;
  double rate = 0.0;  ///< frames per second the description gives; 0 for the overview cameras
  std::uint32_t mount_id = 0;  ///< a robot camera: the instance id of the link it is mounted on
};

/// The scene as `camera` sees it: without the link a robot's camera is mounted on (a camera looks out
/// of its housing, not at it).
render::Scene scene_for(const Session& session, const CameraInfo& camera);

/// Default image size of the overview cameras, pixels.
inline constexpr int kOverviewWidth = 640;
inline constexpr int kOverviewHeight = 480;
/// The follow camera: this far behind the robot and this high, m, pitched down by this much, rad,
/// with this horizontal field of view, rad.
inline constexpr double kFollowDistance = 3.0;
inline constexpr double kFollowHeight = 2.5;
inline constexpr double kFollowPitch = 0.45;
inline constexpr double kFollowFieldOfView = 1.0;

/// Every camera of the session as it is now: overview, follow (when there is a robot), and each camera
/// of each robot with a model (pose from its joints, intrinsics from its description).
std::vector<CameraInfo> cameras_of(const Session& session);

/// One camera by name, at `width` × `height` when given (intrinsics scaled, the field of view kept).
/// Throws core::Error(not_found) naming the cameras there are.
CameraInfo camera_of(const Session& session, const std::string& name, int width = 0, int height = 0);

}  // namespace hrisim::sim
