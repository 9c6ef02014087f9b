#pragma once
// What a planar range sensor can hit at one height: static segments (the map), plus segments and
// circles refreshed every step (closed doors, people's legs or bodies, other robots). A scan is an
// angular sweep: each primitive is mapped to the fan of beams it can cover and only those beams are
// intersected with it — no ray per primitive pair, no physics engine (bench/RESULTS.md compares it
// with Bullet's rayTest).
#include <span>
#include <vector>

#include "core/math.hpp"
#include "world/outline.hpp"

namespace hrisim::sensors {

using core::Vec2;
using world::Segment;

struct Circle {
  Vec2 centre = Vec2::Zero();
  double radius = 0.0;
};

/// The beams of a planar scanner in its own frame: beam i points at start_angle + i × increment.
class BeamFan {
 public:
  BeamFan(double start_angle, double increment, int beams);
  double start_angle() const { return start_angle_; }
  double increment() const { return increment_; }
  int beams() const { return static_cast<int>(cos_.size()); }
  double cos(int beam) const { return cos_[beam]; }
  double sin(int beam) const { return sin_[beam]; }

 private:
  double start_angle_, increment_;
  std::vector<double> cos_, sin_;
};

class RayScene {
 public:
  /// The scene at `height` above the floor: static segments of solids lower than that are left out.
  /// They are referred to, not copied: they must outlive the scene.
  explicit RayScene(std::span<const Segment> static_segments = {}, double height = 0.0)
      : static_(static_segments), height_(height) {}

  void clear_dynamic() {
    segments_.clear();
    circles_.clear();
  }
  void add(const Segment& segment) { segments_.push_back(segment); }
  void add(const Circle& circle) { circles_.push_back(circle); }

  /// Distance along every beam from `origin` (scanner facing `heading`) to the first thing it hits,
  /// +infinity when nothing is within `max_range` (REP 117). Noise-free; `ranges` has fan.beams().
  void scan(const BeamFan& fan, const Vec2& origin, double heading, double max_range, std::span<double> ranges) const;


 private:
  std::span<const Segment> static_;
  double height_;
  std::vector<Segment> segments_;
  std::vector<Circle> circles_;
};

}  // namespace hrisim::sensors
