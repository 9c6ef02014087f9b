#pragma once
// The metrics hrisim computes, as served at GET /api/v1/metrics and listed in docs/metrics.md.
#include <span>
#include <string>
#include <string_view>

namespace hrisim::metrics {

enum class Better { higher, lower, none };

struct Definition {
  std::string_view key;
  std::string_view unit;        ///< "m", "s", "%", "count", "bool", …
  std::string_view category;    ///< the section of METRICS.md it stands in
  Better better;
  std::string_view description;
  std::string_view convention;  ///< the evaluator whose definition it follows
};

std::span<const Definition> definitions();

/// A per-step series kept for plots.
struct SeriesDefinition {
  std::string_view name;
  std::string_view unit;
  std::string_view description;
};
/// distance_to_closest_person, proxemic_zone, time_to_collision, robot_speed, social_force_on_robot.
std::span<const SeriesDefinition> series_definitions();
/// The definition of a key, or nullptr.
const Definition* find_definition(std::string_view key);
std::string_view to_string(Better better);

/// The metrics reference page (docs/metrics.md) in Markdown, from these definitions and the named
/// defaults below: `hrisim metrics` prints it, and a test keeps the file equal to it.
std::string reference_markdown();

// Thresholds of METRICS.md (named defaults, documented in docs/metrics.md).
/// Hall's zones as HuNavSim uses them: intimate below, personal below, social below, m.
inline constexpr double kIntimateDistance = 0.45;
inline constexpr double kPersonalDistance = 1.2;
inline constexpr double kSocialDistance = 3.6;
/// CrowdNav's "danger" (discomfort) distance, m.
inline constexpr double kDiscomfortDistance = 0.2;
/// Surface distance counted as contact even without a physics contact, m.
inline constexpr double kContactDistance = 0.02;
/// Below both, the robot is "not moving": m/s and rad/s.
inline constexpr double kNotMovingSpeed = 0.01;
inline constexpr double kNotMovingTurnRate = 0.02;
/// A collision is blamed on whoever moved towards the other faster than this, m/s.
inline constexpr double kBlameSpeed = 0.01;
/// The panic cost divides by how far a course misses a person (d⊥ − R); below this it counts as this,
/// so that a course grazing someone gives a large cost, not a division by almost zero, m.
inline constexpr double kPanicMissFloor = 0.01;
/// A course that passes within this of grazing a person (d⊥ − R ≤ this) is a collision course, not a
/// near miss: without the margin, rounding in a tangent velocity decides whether it costs anything, m.
inline constexpr double kPanicGrazeMargin = 0.001;
/// A group's centre lies this far ahead of its members (HuNavSim's o-space), m.
inline constexpr double kGroupCentreAhead = 1.5;

// Social forces as HuNavSim's evaluator computes them (lightsfm's formulation, METRICS.md).
inline constexpr double kSocialForceStrength = 2.1;   ///< A
inline constexpr double kSocialForceLambda = 2.0;     ///< λ: weight of the velocity difference
inline constexpr double kSocialForceGamma = 0.35;     ///< γ
inline constexpr double kSocialForceN = 2.0;          ///< n
inline constexpr double kSocialForceNPrime = 3.0;     ///< n′
/// |θ| below this is θ = 0 (e.g. both at rest, where D̂ = e up to rounding and sign(θ) must be 0), rad.
inline constexpr double kSocialForceZeroAngle = 1e-9;
inline constexpr double kObstacleForceStrength = 10.0;  ///< N per unit mass at contact
inline constexpr double kObstacleForceRange = 0.2;      ///< m

/// Failure to progress: the last this many seconds brought the robot less than kProgressDistance closer.
inline constexpr double kProgressWindow = 10.0;
inline constexpr double kProgressDistance = 0.1;

}  // namespace hrisim::metrics
