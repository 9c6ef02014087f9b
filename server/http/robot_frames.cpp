#include "http/robot_frames.hpp"

#include <nlohmann/json.hpp>

#include "sim/session.hpp"

namespace hrisim::http {

std::string base_frame(const std::string& robot) { return robot + "/base_link"; }
std::string sensor_frame(const std::string& robot, const std::string& sensor) { return robot + "/" + sensor; }

std::string camera_frame(const std::string& camera) {
  const std::size_t dot = camera.find('.');
  return dot == std::string::npos ? kMapFrame : sensor_frame(camera.substr(0, dot), camera.substr(dot + 1));
}

Eigen::Isometry3d planar(const core::Pose2& pose, double height) {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.translate(Eigen::Vector3d(pose.x, pose.y, height));
  transform.rotate(Eigen::AngleAxisd(pose.theta, Eigen::Vector3d::UnitZ()));
  return transform;
}

std::vector<FrameTransform> robot_frames(const sim::Session& session) {
  std::vector<FrameTransform> frames;
  const auto& agents = session.model().agents;
  for (std::size_t a = 0; a < agents.size(); ++a) {
    const sim::RobotRuntime* runtime = agents[a].kind == scenario::AgentKind::robot ? session.robot_runtime(session.agent_at(static_cast<int>(a))) : nullptr;
    if (!runtime) continue;
    const Eigen::Isometry3d base = planar(runtime->robot.pose());
    frames.push_back({kMapFrame, base_frame(agents[a].id), base, false});
    for (const robots::Sensor& sensor : agents[a].robot_model->sensors) {
      frames.push_back({base_frame(agents[a].id), sensor_frame(agents[a].id, sensor.name), base.inverse() * runtime->robot.sensor_pose(sensor), true});
    }
  }
  return frames;
}

nlohmann::json vector3(const Eigen::Vector3d& v) { return {{"x", v.x()}, {"y", v.y()}, {"z", v.z()}}; }

nlohmann::json quaternion(const Eigen::Quaterniond& q) { return {{"x", q.x()}, {"y", q.y()}, {"z", q.z()}, {"w", q.w()}}; }

nlohmann::json pose(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation) {
  return {{"position", vector3(position)}, {"orientation", quaternion(orientation)}};
}

nlohmann::json pose(const Eigen::Isometry3d& transform) { return pose(transform.translation(), Eigen::Quaterniond(transform.linear())); }

}  // namespace hrisim::http
