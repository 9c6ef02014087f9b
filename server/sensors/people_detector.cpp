#include "sensors/people_detector.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "core/portable_math.hpp"

namespace hrisim::sensors {
namespace {

/// Beams of the visibility sweep: the field of view at the angular resolution.
int sweep_beams(const PeopleDetectorParams& params) {
  return std::max(2, static_cast<int>(std::ceil(params.field_of_view / params.angular_resolution)) + 1);
}

/// A body the ray to its centre reaches within this of its near side is seen, m.
constexpr double kVisibilityTolerance = 1e-3;

}  // namespace

PeopleDetectorParams read_people_detector_params(const nlohmann::json& settings, PeopleDetectorParams defaults) {
  PeopleDetectorParams params = defaults;
  params.field_of_view = settings.value("field_of_view", params.field_of_view);
  params.range = settings.value("range", params.range);
  params.position_noise = settings.value("position_noise", params.position_noise);
  params.velocity_noise = settings.value("velocity_noise", params.velocity_noise);
  params.miss_probability = settings.value("miss_probability", params.miss_probability);
  params.rate = settings.value("rate", params.rate);
  params.face_range = settings.value("face_range", params.face_range);
  params.face_max_yaw = settings.value("face_max_yaw", params.face_max_yaw);
  return params;
}

PeopleDetector::PeopleDetector(PeopleDetectorParams params)
    : params_(params),
      fan_(-0.5 * params.field_of_view, params.field_of_view / (sweep_beams(params) - 1), sweep_beams(params)) {}

void PeopleDetector::detect(const RayScene& scene, const Vec2& origin, double heading, std::span<const PersonTruth> people,
                            core::Random& random, std::vector<Detection>& detections) const {
  detections.clear();
  visibility_.resize(static_cast<std::size_t>(fan_.beams()));
  scene.scan(fan_, origin, heading, params_.range, visibility_);
  for (const PersonTruth& person : people) {
    // The same draws for everyone, seen or not, so one person's visibility never shifts another's noise.
    const bool missed = random.uniform() < params_.miss_probability;
    const Vec2 position_error(random.normal(0.0, params_.position_noise), random.normal(0.0, params_.position_noise));
    const Vec2 velocity_error(random.normal(0.0, params_.velocity_noise), random.normal(0.0, params_.velocity_noise));
    const Vec2 offset = person.position - origin;
    const double distance = offset.norm();
    if (distance > params_.range || distance <= person.radius || missed) continue;
    const double bearing = core::wrap_angle(core::polynomial_atan2(offset.y(), offset.x()) - heading);
    if (std::abs(bearing) > 0.5 * params_.field_of_view) continue;
    const int beam = static_cast<int>(std::lround((bearing - fan_.start_angle()) / fan_.increment()));
    if (visibility_[std::clamp(beam, 0, fan_.beams() - 1)] < distance - person.radius - kVisibilityTolerance) continue;
    Detection detection{person.agent, person.position + position_error, person.velocity + velocity_error, 0.0, 0.0};
    const Vec2 seen = detection.position - origin;
    detection.range = seen.norm();
    detection.bearing = core::wrap_angle(core::polynomial_atan2(seen.y(), seen.x()) - heading);
    const double yaw = core::wrap_angle(core::polynomial_atan2(-offset.y(), -offset.x()) - person.heading);
    detection.face_visible = distance <= params_.face_range && std::abs(yaw) <= params_.face_max_yaw;
    detections.push_back(detection);
  }
}

}  // namespace hrisim::sensors
