#pragma once
// Planar geometry in the map frame (REP 103: x forward, y left, angles counter-clockwise in radians).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace hrisim::core {

using Vec2 = Eigen::Vector2d;

/// A 2D pose: position and heading.
struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;

  Vec2 position() const { return {x, y}; }
  bool operator==(const Pose2&) const = default;
};

/// A 3D pose (DESIGN §3): position and roll, pitch, yaw (rotations about x, y, z, applied in that
/// order in the fixed frame, as URDF's rpy).
struct Pose3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
  double roll = 0.0;
  double pitch = 0.0;
  double yaw = 0.0;

  bool operator==(const Pose3&) const = default;
};

/// Angle wrapped into (-π, π].
inline double wrap_angle(double angle) {
  if (angle > -std::numbers::pi && angle <= std::numbers::pi) return angle;  // the usual case, without libm
  angle = std::remainder(angle, 2.0 * std::numbers::pi);
  return angle <= -std::numbers::pi ? angle + 2.0 * std::numbers::pi : angle;
}

/// The vector rotated by +90°.
inline Vec2 left_normal(const Vec2& v) { return {-v.y(), v.x()}; }

/// "x, y" with up to six significant digits, for messages: "9, 1", "2.5, -0.333333".
std::string point_text(const Vec2& p);
/// A number with up to six significant digits, for messages: "1.21", "-0.333333".
std::string number_text(double value);

/// 2D cross product (z of the 3D one).
/// Heading of the direction from `from` to `to`, rad.
inline double direction_to(const Vec2& from, const Vec2& to) { return std::atan2(to.y() - from.y(), to.x() - from.x()); }
inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
/// Whether segments ab and cd cross (touching counts).
inline bool segments_cross(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double d1 = cross(b - a, c - a), d2 = cross(b - a, d - a), d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
  return d1 * d2 <= 0.0 && d3 * d4 <= 0.0;
}

/// Unit vector of heading theta.
inline Vec2 heading_vector(double theta) { return {std::cos(theta), std::sin(theta)}; }

/// A map-frame vector in the frame of something heading `theta` (x ahead, y left).
inline Vec2 in_frame(double theta, const Vec2& v) {
  const double c = std::cos(theta), s = std::sin(theta);
  return {c * v.x() + s * v.y(), -s * v.x() + c * v.y()};
}

/// Closest point to p on segment [a, b].
inline Vec2 closest_point_on_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double length_squared = ab.squaredNorm();
  if (length_squared == 0.0) return a;
  const double t = std::clamp((p - a).dot(ab) / length_squared, 0.0, 1.0);
  return a + t * ab;
}

/// Pose `offset` expressed in the frame of `base`, returned in the map frame.
inline Pose2 compose(const Pose2& base, const Pose2& offset) {
  const double c = std::cos(base.theta), s = std::sin(base.theta);
  return {base.x + c * offset.x - s * offset.y, base.y + s * offset.x + c * offset.y,
          wrap_angle(base.theta + offset.theta)};
}

}  // namespace hrisim::core
