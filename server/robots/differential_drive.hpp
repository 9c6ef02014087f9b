#pragma once
// Kinematics of a differential-drive base (HSR, ARTOS): body velocity ↔ wheel speeds, and the exact
// pose update for wheels turning at constant speed over one tick (a circular arc).
#include "core/math.hpp"

namespace hrisim::robots {

using core::Pose2;

struct DifferentialDriveParams {
  double wheel_radius = 0.04;      ///< m
  double wheel_separation = 0.266; ///< m, between the wheels' contact points
  double max_linear_speed = 0.8 / 3.6;  ///< m/s
  double max_angular_speed = 1.0;       ///< rad/s
};

/// Linear (m/s, forward) and angular (rad/s, counter-clockwise) velocity of the body.
struct Twist {
  double linear = 0.0;
  double angular = 0.0;
};

/// Wheel angular velocities, rad/s (positive rolls the robot forward).
struct WheelSpeeds {
  double left = 0.0;
  double right = 0.0;
};

/// The command clamped to the base's linear and angular limits (each on its own, as ROS's
/// diff_drive_controller limits them).
Twist limit(const DifferentialDriveParams& params, const Twist& command);
/// Wheel speeds that realise the twist.
WheelSpeeds wheel_speeds(const DifferentialDriveParams& params, const Twist& twist);
/// The body twist the wheel speeds produce.
Twist body_twist(const DifferentialDriveParams& params, const WheelSpeeds& wheels);
/// The pose after moving with the twist for dt (exact arc, straight line when not turning).
Pose2 integrate(const Pose2& pose, const Twist& twist, double dt);

}  // namespace hrisim::robots
