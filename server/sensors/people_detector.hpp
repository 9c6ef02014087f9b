#pragma once
// The perception a navigation stack under test would get: positions and velocities of the people
// within a field of view and range that the sensor can see (line of sight past walls, furniture and
// other people), with position and velocity noise and a probability of missing someone.
#include <span>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "core/random.hpp"
#include "sensors/ray_scene.hpp"

namespace hrisim::sensors {

/// A face is found within this range: a frontal face detector's smallest window (Viola and Jones's
/// 24 px) on a 0.15 m wide face, through a 640 px camera with a 1.0 rad field of view (ARTOS's), m.
inline constexpr double kFaceRange = 3.5;
/// ...and when the person faces the camera within this angle: frontal detectors find faces up to
/// about 45 degrees of yaw; profiles need their own, rad.
inline constexpr double kFaceMaxYaw = 0.7853981633974483;

struct PeopleDetectorParams {
  double field_of_view = 270.0 * 3.14159265358979323846 / 180.0;  ///< rad, centred on the sensor's x axis
  double range = 10.0;              ///< m
  double position_noise = 0.05;     ///< m, standard deviation per axis
  double velocity_noise = 0.1;      ///< m/s, standard deviation per axis
  double miss_probability = 0.05;   ///< a visible person goes unreported
  double rate = 10.0;               ///< Hz
  double angular_resolution = 0.25 * 3.14159265358979323846 / 180.0;  ///< rad, of the visibility sweep
  double face_range = kFaceRange;      ///< m
  double face_max_yaw = kFaceMaxYaw;   ///< rad
};

PeopleDetectorParams read_people_detector_params(const nlohmann::json& settings, PeopleDetectorParams defaults = {});

/// A person as the simulation knows them.
struct PersonTruth {
  int agent = -1;
  Vec2 position = Vec2::Zero();
  Vec2 velocity = Vec2::Zero();
  double radius = 0.2;  ///< of the body at the sensor's height
  double heading = 0.0;  ///< where the person faces, rad
};

struct Detection {
  int agent = -1;
  Vec2 position = Vec2::Zero();  ///< map frame, with noise
  Vec2 velocity = Vec2::Zero();  ///< map frame, with noise
  double range = 0.0;            ///< from the sensor to the noisy position, m
  double bearing = 0.0;          ///< in the sensor frame, rad
  bool face_visible = false;     ///< within face_range and facing the sensor within face_max_yaw
};

class PeopleDetector {
 public:
  explicit PeopleDetector(PeopleDetectorParams params);
  const PeopleDetectorParams& params() const { return params_; }

  /// `scene` holds the map and the people's bodies at the sensor's height. A person counts as visible
  /// when the ray to their centre reaches their body first.
  void detect(const RayScene& scene, const Vec2& origin, double heading, std::span<const PersonTruth> people,
              core::Random& random, std::vector<Detection>& detections) const;

 private:
  PeopleDetectorParams params_;
  BeamFan fan_;
  mutable std::vector<double> visibility_;  ///< scratch of detect
};

}  // namespace hrisim::sensors
