#pragma once
// The built-in robot controllers' laws: from the robot's pose, the path ahead and the people around,
// a base command. The session's robot-control phase picks one per robot (docs/robots/controllers.md).
#include <vector>

#include "core/math.hpp"
#include "robots/differential_drive.hpp"

namespace hrisim::robots {

using core::Pose2;
using core::Vec2;

// Named defaults, documented in docs/robots/controllers.md.
/// Pure pursuit looks this far ahead along the path, m.
inline constexpr double kPurePursuitLookahead = 0.6;
/// ...or less at low speed: as far as the robot drives in this time, but no less than
/// kMinPurePursuitLookahead (a long lookahead at walking pace cuts corners into walls), s.
inline constexpr double kPurePursuitLookaheadTime = 1.5;
inline constexpr double kMinPurePursuitLookahead = 0.25;
/// A target further to the side than this is first faced by turning on the spot, rad.
inline constexpr double kTurnOnTheSpotAngle = 0.8;
/// Angular velocity per radian of heading error when facing a direction, 1/s.
inline constexpr double kHeadingGain = 2.5;
/// Robots slow down over this distance before their goal, m.
inline constexpr double kRobotArrivalSlowdown = 0.5;
/// The social robot slows for a person closer than this within ±kSocialYieldAngle ahead, m...
inline constexpr double kSocialSlowDistance = 1.5;
/// ...and stops for one this close, m.
inline constexpr double kSocialStopDistance = 0.6;
inline constexpr double kSocialYieldAngle = 1.0;  ///< rad
/// The social robot's sideways push away from people: strength at contact (m/s) and decay length (m),
/// Helbing's exponential repulsion.
inline constexpr double kSocialRepulsion = 0.5;
inline constexpr double kSocialRepulsionRange = 0.4;

/// The point `distance` further along the path from `start` through the waypoints (the last one when the
/// path is shorter).
Vec2 point_along(const Vec2& start, const std::vector<Vec2>& path, double distance);
/// The length of the path from `start` through the waypoints.
double remaining_length(const Vec2& start, const std::vector<Vec2>& path);
/// The point a path follower at `speed` aims at: a lookahead (speed × kPurePursuitLookaheadTime, within
/// [kMinPurePursuitLookahead, kPurePursuitLookahead]) along the path, or its end.
Vec2 lookahead_point(const Vec2& position, const std::vector<Vec2>& path, double speed);
/// The velocity a path follower at `speed` wants: towards the point a lookahead ahead, slowed before
/// the last waypoint (as pure pursuit); zero for an empty path.
Vec2 path_velocity(const Vec2& position, const std::vector<Vec2>& path, double speed);

/// Pure pursuit along `path` (from the robot's position through the remaining waypoints): the arc
/// through the point a lookahead ahead (speed × kPurePursuitLookaheadTime, within [kMinPurePursuitLookahead, kPurePursuitLookahead]), at `speed`; turns on the spot towards targets far to
/// the side; slows before the last waypoint.
Twist pure_pursuit(const Pose2& pose, const std::vector<Vec2>& path, double speed);

/// A differential-drive command that follows a desired planar velocity: turn on the spot towards it when
/// it points further than `turn_angle` away, else drive at its speed projected on the heading (never
/// backwards) while turning towards it.
Twist follow_velocity(const Pose2& pose, const Vec2& desired, double turn_angle = kTurnOnTheSpotAngle);

/// The social robot's desired velocity: towards the lookahead point at `speed`, pushed sideways away
/// from nearby people, slowed and stopped for people ahead.
Vec2 social_velocity(const Pose2& pose, const std::vector<Vec2>& path, double speed, const std::vector<Vec2>& people,
                     double robot_radius);

}  // namespace hrisim::robots
