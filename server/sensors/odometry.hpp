#pragma once
// Wheel odometry: the pose a robot believes from integrating the twist its wheels measure, with
// drift — random errors whose variance grows with the distance driven and the angle turned (so they
// do not depend on the step size), and an optional systematic scale error. Starts at the origin of
// the odometry frame, as a real robot's does.
#include <nlohmann/json_fwd.hpp>

#include "core/math.hpp"
#include "core/random.hpp"
#include "core/state_hash.hpp"
#include "robots/differential_drive.hpp"

namespace hrisim::sensors {

struct OdometryParams {
  double translation_noise = 0.01;  ///< m per √m driven: standard deviation of the distance error
  double heading_noise_per_metre = 0.01;  ///< rad per √m driven
  double heading_noise_per_radian = 0.01; ///< rad per √rad turned
  double scale_error = 0.0;  ///< relative, systematic: measured distance = (1 + scale_error) × true
  double rate = 50.0;        ///< Hz
};

OdometryParams read_odometry_params(const nlohmann::json& settings, OdometryParams defaults = {});

class Odometry {
 public:
  explicit Odometry(OdometryParams params = {}) : params_(params) {}

  /// Integrates one step of the measured twist over dt, adding drift from `random`.
  void update(const robots::Twist& measured, double dt, core::Random& random);

  const core::Pose2& pose() const { return pose_; }
  const robots::Twist& twist() const { return twist_; }
  const OdometryParams& params() const { return params_; }
  void hash(core::StateHasher& hasher) const;

 private:
  OdometryParams params_;
  core::Pose2 pose_;
  robots::Twist twist_;
};

}  // namespace hrisim::sensors
