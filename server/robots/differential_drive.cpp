#include "robots/differential_drive.hpp"

#include <algorithm>
#include <cmath>

namespace hrisim::robots {

Twist limit(const DifferentialDriveParams& params, const Twist& command) {
  return {std::clamp(command.linear, -params.max_linear_speed, params.max_linear_speed),
          std::clamp(command.angular, -params.max_angular_speed, params.max_angular_speed)};
}

WheelSpeeds wheel_speeds(const DifferentialDriveParams& params, const Twist& twist) {
  const double half_track = 0.5 * params.wheel_separation;
  return {(twist.linear - twist.angular * half_track) / params.wheel_radius,
          (twist.linear + twist.angular * half_track) / params.wheel_radius};
}

Twist body_twist(const DifferentialDriveParams& params, const WheelSpeeds& wheels) {
  const double left = wheels.left * params.wheel_radius, right = wheels.right * params.wheel_radius;
  return {0.5 * (left + right), (right - left) / params.wheel_separation};
}

Pose2 integrate(const Pose2& pose, const Twist& twist, double dt) {
  const double turn = twist.angular * dt;
  if (std::abs(turn) < 1e-9) {
    // Straight (the arc formula divides by the turn); the midpoint heading keeps it second-order exact.
    const double heading = pose.theta + 0.5 * turn;
    return {pose.x + twist.linear * dt * std::cos(heading), pose.y + twist.linear * dt * std::sin(heading),
            core::wrap_angle(pose.theta + turn)};
  }
  const double radius = twist.linear / twist.angular;
  const double theta = pose.theta + turn;
  return {pose.x + radius * (std::sin(theta) - std::sin(pose.theta)),
          pose.y - radius * (std::cos(theta) - std::cos(pose.theta)), core::wrap_angle(theta)};
}

}  // namespace hrisim::robots
