#pragma once
// Episode metrics of METRICS.md computed from a Recording. Pure: the same recording gives the same
// values, and nothing outside the recording is read.
#include <optional>
#include <string>
#include <vector>

#include "metrics/recording.hpp"

namespace hrisim::metrics {

/// A metric's value, or no value and why (never NaN or infinity).
struct MetricValue {
  std::string key;
  std::optional<double> value;
  std::string null_reason;  ///< set exactly when value is empty
};

/// Every metric of definitions(), in that order.
std::vector<MetricValue> compute_episode_metrics(const Recording& recording);

/// Mean over the people present in both recordings of the extra path each walked in `with_robot`
/// compared with `without_robot` (the same seed run with the robot taken out): the robot's
/// disturbance of the people. Empty when no person is in both.
std::optional<double> human_path_deviation(const Recording& with_robot, const Recording& without_robot);

/// A per-step series for plots: one value (or none) per sample of the recording.
struct Series {
  std::string name;
  std::string unit;
  std::vector<std::optional<double>> values;
};

/// The series of series_definitions(), in that order, one value per sample; empty values where a step
/// has none (no person, no collision course, no robot).
std::vector<Series> compute_series(const Recording& recording);

/// Surface distance between two discs: centre distance minus both radii, at least 0.
double surface_distance(const Body& a, const Body& b);

/// lightsfm's social force of agent `from` on agent `on` (per unit mass), as METRICS.md writes it;
/// zero for coincident agents.
Vec2 social_force(const Body& on, const Body& from);

/// Earliest time >= 0 at which two discs moving at their current velocities touch; 0 when they
/// already overlap, empty when they never do.
std::optional<double> time_to_collision(const Body& a, const Body& b);

}  // namespace hrisim::metrics
