#include "sensors/ray_scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/portable_math.hpp"

namespace hrisim::sensors {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// Angle in [0, 2π).
double positive_angle(double angle) {
  angle = std::fmod(angle, kTwoPi);
  return angle < 0.0 ? angle + kTwoPi : angle;
}

/// Calls f(beam) for every beam whose direction lies within the arc [from, from + span] (angles
/// relative to the fan's start, from in [0, 2π), span ≤ π), one beam of margin each side: the exact
/// intersection test decides.
template <class F>
void for_beams_in_arc(const BeamFan& fan, double from, double span, F&& f) {
  const double increment = fan.increment();
  const int beams = fan.beams();
  if (beams == 1) {  // a single beam (infrared): the exact test decides
    f(0);
    return;
  }
  auto piece = [&](double low, double high) {
    const int first = std::max(0, static_cast<int>(std::floor(low / increment)) - 1);
    const int last = std::min(beams - 1, static_cast<int>(std::ceil(high / increment)) + 1);
    for (int beam = first; beam <= last; ++beam) f(beam);
  };
  if (from + span < kTwoPi) {
    piece(from, from + span);
  } else {  // the arc passes the fan's start angle
    piece(from, kTwoPi);
    piece(0.0, from + span - kTwoPi);
  }
}

}  // namespace

BeamFan::BeamFan(double start_angle, double increment, int beams) : start_angle_(start_angle), increment_(increment) {
  for (int i = 0; i < beams; ++i) {
    const double angle = start_angle + i * increment;
    cos_.push_back(std::cos(angle));
    sin_.push_back(std::sin(angle));
  }
}

void RayScene::scan(const BeamFan& fan, const Vec2& origin, double heading, double max_range, std::span<double> ranges) const {
  const double infinity = std::numeric_limits<double>::infinity();
  std::fill(ranges.begin(), ranges.end(), infinity);
  const double c = std::cos(heading), s = std::sin(heading);
  auto direction = [&](int beam) { return Vec2(c * fan.cos(beam) - s * fan.sin(beam), s * fan.cos(beam) + c * fan.sin(beam)); };
  const double fan_start = heading + fan.start_angle();
  auto relative_angle = [&](const Vec2& v) { return positive_angle(core::polynomial_atan2(v.y(), v.x()) - fan_start); };

  auto sweep_segment = [&](const Segment& segment) {
    const Vec2 p = segment.a - origin, q = segment.b - origin;
    const Vec2 edge = q - p;
    if (segment.one_sided && core::cross(edge, -p) <= 0.0) return;  // we are behind it, inside the solid
    if ((core::closest_point_on_segment(Vec2::Zero(), p, q)).norm() > max_range) return;
    // The arc the segment covers: from one end's angle, the short way (< π) to the other's.
    const double angle_p = relative_angle(p);
    const double turn = core::wrap_angle(relative_angle(q) - angle_p);
    const double from = turn >= 0.0 ? angle_p : positive_angle(angle_p + turn);
    for_beams_in_arc(fan, from, std::abs(turn), [&](int beam) {
      const Vec2 d = direction(beam);
      const double denominator = core::cross(d, edge);
      if (denominator == 0.0) return;
      const double t = core::cross(p, edge) / denominator;
      const double u = core::cross(p, d) / denominator;
      if (t > 0.0 && u >= 0.0 && u <= 1.0 && t < ranges[beam]) ranges[beam] = t;
    });
  };
  for (const Segment& segment : static_) {
    if (segment.top > height_) sweep_segment(segment);
  }
  for (const Segment& segment : segments_) sweep_segment(segment);

  for (const Circle& circle : circles_) {
    const Vec2 centre = circle.centre - origin;
    const double distance_squared = centre.squaredNorm(), radius_squared = circle.radius * circle.radius;
    const double distance = std::sqrt(distance_squared);
    if (distance - circle.radius > max_range) continue;
    if (distance_squared <= radius_squared) {
      std::fill(ranges.begin(), ranges.end(), 0.0);  // the scanner is inside it: blind
      return;
    }
    const double half_width = core::polynomial_atan2(circle.radius, std::sqrt(distance_squared - radius_squared));
    const double from = positive_angle(relative_angle(centre) - half_width);
    for_beams_in_arc(fan, from, 2.0 * half_width, [&](int beam) {
      const Vec2 d = direction(beam);
      const double along = d.dot(centre);
      const double discriminant = radius_squared - (distance_squared - along * along);
      if (along <= 0.0 || discriminant < 0.0) return;
      const double t = along - std::sqrt(discriminant);
      if (t < ranges[beam]) ranges[beam] = t;
    });
  }
  for (double& range : ranges) {
    if (range > max_range) range = infinity;
  }
}

}  // namespace hrisim::sensors
