#pragma once
// A 2D laser range finder: a fan of beams with range limits, Gaussian range noise and a rate. The
// defaults are a Hokuyo UST-20LX class scanner (HSR's base laser): 270°, 0.25° steps = 1081 beams,
// 0.02–20 m, 40 Hz. An infrared distance sensor is the same with one beam (its own defaults).
#include <span>
#include <vector>

#include "core/random.hpp"
#include "robots/description.hpp"
#include "sensors/ray_scene.hpp"

namespace hrisim::sensors {

struct LaserParams {
  double field_of_view = 270.0 * 3.14159265358979323846 / 180.0;  ///< rad, centred on the sensor's x axis
  int beams = 1081;
  double min_range = 0.02;  ///< m: closer returns read -infinity (REP 117)
  double max_range = 20.0;  ///< m: nothing within reads +infinity
  double range_noise = 0.01;  ///< m, standard deviation
  double rate = 40.0;       ///< Hz

  /// Angle between neighbouring beams (the whole field for a single beam).
  double increment() const { return beams > 1 ? field_of_view / (beams - 1) : 0.0; }
  double start_angle() const { return beams > 1 ? -0.5 * field_of_view : 0.0; }
};

/// A Sharp GP2Y0A21-class infrared distance sensor: one beam, 0.1–0.8 m.
LaserParams infrared_defaults();

/// The defaults overridden by a description's "laser" settings (api/robot.schema.json).
LaserParams read_laser_params(const robots::RangeSettings& settings, LaserParams defaults = {});

class Laser {
 public:
  explicit Laser(LaserParams params);
  const LaserParams& params() const { return params_; }

  /// One scan from the sensor at `origin` facing `heading`, with range noise from `random`.
  void scan(const RayScene& scene, const Vec2& origin, double heading, core::Random& random, std::vector<double>& ranges) const;

 private:
  LaserParams params_;
  BeamFan fan_;
};

}  // namespace hrisim::sensors
