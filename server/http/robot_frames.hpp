#pragma once
// The frames a bridge places a session's robots and sensors in (the Foxglove and rosbridge sockets
// share them): the fixed map frame, each robot's base under it, each sensor under its robot's base.
#include <Eigen/Geometry>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "core/math.hpp"

namespace hrisim::sim {
class Session;
}

namespace hrisim::http {

inline constexpr const char* kMapFrame = "map";
std::string base_frame(const std::string& robot);                               ///< ROBOT/base_link
std::string sensor_frame(const std::string& robot, const std::string& sensor);  ///< ROBOT/SENSOR
/// The frame a camera's images are taken in: ROBOT/SENSOR for a robot's camera (named ROBOT.SENSOR),
/// the map for the scene's own cameras.
std::string camera_frame(const std::string& camera);

/// A pose on the floor plane, `height` above it, as a transform.
Eigen::Isometry3d planar(const core::Pose2& pose, double height = 0.0);

/// Where a frame is in its parent.
struct FrameTransform {
  std::string parent, child;
  Eigen::Isometry3d pose;
  bool sensor;  ///< a sensor under its robot's base (else a robot's base in the map)
};
/// map → ROBOT/base_link for every robot with a model, and ROBOT/base_link → ROBOT/SENSOR for each
/// sensor of its description, as they are now.
std::vector<FrameTransform> robot_frames(const sim::Session& session);

/// Positions, rotations and poses as both bridges' messages spell them (ROS's geometry_msgs and
/// Foxglove's schemas agree: x, y, z; x, y, z, w; position and orientation).
nlohmann::json vector3(const Eigen::Vector3d& v);
nlohmann::json quaternion(const Eigen::Quaterniond& q);
nlohmann::json pose(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation);
nlohmann::json pose(const Eigen::Isometry3d& transform);

}  // namespace hrisim::http
