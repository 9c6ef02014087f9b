#include "sensors/laser.hpp"

#include <cmath>
#include <limits>

namespace hrisim::sensors {

LaserParams infrared_defaults() {
  LaserParams params;
  params.field_of_view = 0.0;
  params.beams = 1;
  params.min_range = 0.1;
  params.max_range = 0.8;
  params.range_noise = 0.01;
  params.rate = 25.0;
  return params;
}

LaserParams read_laser_params(const robots::RangeSettings& settings, LaserParams defaults) {
  LaserParams params = defaults;
  params.field_of_view = settings.field_of_view.value_or(params.field_of_view);
  params.beams = settings.beams.value_or(params.beams);
  params.min_range = settings.min_range.value_or(params.min_range);
  params.max_range = settings.max_range.value_or(params.max_range);
  params.range_noise = settings.range_noise.value_or(params.range_noise);
  params.rate = settings.rate.value_or(params.rate);
  return params;
}

Laser::Laser(LaserParams params) : params_(params), fan_(params.start_angle(), params.increment(), params.beams) {}

void Laser::scan(const RayScene& scene, const Vec2& origin, double heading, core::Random& random, std::vector<double>& ranges) const {
  ranges.resize(static_cast<std::size_t>(params_.beams));
  scene.scan(fan_, origin, heading, params_.max_range, ranges);
  for (double& range : ranges) {
    if (!std::isfinite(range)) continue;
    // Too close (the scanner inside something, or nearer than it measures) reads -infinity before
    // and after the noise.
    if (range >= params_.min_range && params_.range_noise > 0.0) range += random.normal(0.0, params_.range_noise);
    if (range < params_.min_range) {
      range = -std::numeric_limits<double>::infinity();
    } else if (range > params_.max_range) {
      range = std::numeric_limits<double>::infinity();
    }
  }
}

}  // namespace hrisim::sensors
