#include "robots/controllers.hpp"

#include <algorithm>
#include <cmath>

#include "core/portable_math.hpp"

namespace hrisim::robots {

namespace {

/// How far ahead along the path a follower at `speed` aims.
double lookahead(double speed) { return std::clamp(speed * kPurePursuitLookaheadTime, kMinPurePursuitLookahead, kPurePursuitLookahead); }

/// The share of its speed a follower keeps with `remaining` metres to go.
double arrival_share(double remaining) { return std::clamp(remaining / kRobotArrivalSlowdown, 0.2, 1.0); }

}  // namespace

Vec2 point_along(const Vec2& start, const std::vector<Vec2>& path, double distance) {
  Vec2 from = start;
  for (const Vec2& to : path) {
    const double leg = (to - from).norm();
    if (leg >= distance) return from + (to - from) * (distance / std::max(leg, 1e-12));
    distance -= leg;
    from = to;
  }
  return from;
}

double remaining_length(const Vec2& start, const std::vector<Vec2>& path) {
  double length = 0.0;
  Vec2 from = start;
  for (const Vec2& to : path) {
    length += (to - from).norm();
    from = to;
  }
  return length;
}

Vec2 lookahead_point(const Vec2& position, const std::vector<Vec2>& path, double speed) {
  return point_along(position, path, std::min(lookahead(speed), remaining_length(position, path)));
}

Vec2 path_velocity(const Vec2& position, const std::vector<Vec2>& path, double speed) {
  if (path.empty()) return Vec2::Zero();
  const Vec2 offset = lookahead_point(position, path, speed) - position;
  if (offset.norm() < 1e-9) return Vec2::Zero();
  return offset.normalized() * speed * arrival_share(remaining_length(position, path));
}

Twist pure_pursuit(const Pose2& pose, const std::vector<Vec2>& path, double speed) {
  if (path.empty()) return {};
  const Vec2 position = pose.position();
  const double remaining = remaining_length(position, path);
  const Vec2 offset = lookahead_point(position, path, speed) - position;
  if (offset.norm() < 1e-9) return {};
  // The target in the robot's frame; the arc through it has curvature 2y / L².
  const Vec2 local = core::in_frame(pose.theta, offset);
  const double ahead = local.x(), left = local.y();
  const double bearing = core::polynomial_atan2(left, ahead);
  if (std::abs(bearing) > kTurnOnTheSpotAngle) return {0.0, kHeadingGain * bearing};
  const double linear = speed * arrival_share(remaining);
  return {linear, linear * 2.0 * left / offset.squaredNorm()};
}

Twist follow_velocity(const Pose2& pose, const Vec2& desired, double turn_angle) {
  const double speed = desired.norm();
  if (speed < 1e-6) return {};
  const double error = core::wrap_angle(core::polynomial_atan2(desired.y(), desired.x()) - pose.theta);
  if (std::abs(error) > turn_angle) return {0.0, kHeadingGain * error};
  return {speed * std::cos(error), kHeadingGain * error};
}

Vec2 social_velocity(const Pose2& pose, const std::vector<Vec2>& path, double speed, const std::vector<Vec2>& people,
                     double robot_radius) {
  if (path.empty()) return Vec2::Zero();
  const Vec2 position = pose.position();
  const Vec2 onwards = path_velocity(position, path, speed);
  const Vec2 forward = core::heading_vector(pose.theta);
  double slowest = 1.0;
  Vec2 push = Vec2::Zero();
  for (const Vec2& person : people) {
    const Vec2 away = position - person;
    const double gap = away.norm() - robot_radius;
    if (gap > kSocialSlowDistance + 1.0) continue;
    // Away from the person and, as people do, round them on the right: a standing person right
    // ahead pushes straight back, and the sideways share lets the robot pass instead of waiting.
    const Vec2 away_unit = away.normalized(), right_of_person(-away_unit.y(), away_unit.x());
    push += kSocialRepulsion * std::exp(-std::max(gap, 0.0) / kSocialRepulsionRange) * (away_unit + right_of_person);
    const double angle = std::acos(std::clamp(forward.dot(-away_unit), -1.0, 1.0));
    if (angle < kSocialYieldAngle) {
      slowest = std::min(slowest, std::clamp((gap - kSocialStopDistance) / (kSocialSlowDistance - kSocialStopDistance), 0.0, 1.0));
    }
  }
  // Yielding slows the progress along the path, not the way round the people.
  return onwards * slowest + push;
}

}  // namespace hrisim::robots
