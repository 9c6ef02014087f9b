#include "sensors/odometry.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

namespace hrisim::sensors {

OdometryParams read_odometry_params(const nlohmann::json& settings, OdometryParams defaults) {
  OdometryParams params = defaults;
  params.translation_noise = settings.value("translation_noise", params.translation_noise);
  params.heading_noise_per_metre = settings.value("heading_noise_per_metre", params.heading_noise_per_metre);
  params.heading_noise_per_radian = settings.value("heading_noise_per_radian", params.heading_noise_per_radian);
  params.scale_error = settings.value("scale_error", params.scale_error);
  params.rate = settings.value("rate", params.rate);
  return params;
}

void Odometry::update(const robots::Twist& measured, double dt, core::Random& random) {
  const double distance = std::abs(measured.linear) * dt, turned = std::abs(measured.angular) * dt;
  // Standard deviations ∝ √(distance): the variances of many small steps add up to that of one long one.
  double step = (1.0 + params_.scale_error) * measured.linear * dt;
  if (distance > 0.0 && params_.translation_noise > 0.0) step += random.normal(0.0, params_.translation_noise * std::sqrt(distance));
  double turn = measured.angular * dt;
  const double heading_variance = params_.heading_noise_per_metre * params_.heading_noise_per_metre * distance +
                                  params_.heading_noise_per_radian * params_.heading_noise_per_radian * turned;
  if (heading_variance > 0.0) turn += random.normal(0.0, std::sqrt(heading_variance));
  twist_ = {step / dt, turn / dt};
  pose_ = robots::integrate(pose_, twist_, dt);
}

void Odometry::hash(core::StateHasher& hasher) const {
  hasher.add(pose_.x).add(pose_.y).add(pose_.theta).add(twist_.linear).add(twist_.angular);
}

}  // namespace hrisim::sensors
