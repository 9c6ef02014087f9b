#pragma once
// Reference local planners a researcher compares a new robot controller against, all following the
// same global path: the Dynamic Window Approach (Fox, Burgard & Thrun 1997), ORCA for one robot that
// does not count on people to avoid it (van den Berg et al. 2011), and the social force model with
// HuNavSim's parameters (Helbing & Molnár 1995, Moussaïd et al. 2009). They see people's true
// positions and velocities and the static obstacles (docs/robots/controllers.md).
#include <span>
#include <vector>

#include "core/math.hpp"
#include "humans/locomotion.hpp"
#include "robots/differential_drive.hpp"

namespace hrisim::robots {

using core::Vec2;

// Named defaults, documented in docs/robots/controllers.md.
/// DWA: each candidate velocity is held over this horizon to score it, s...
inline constexpr double kDwaPredictionTime = 2.0;
/// ...predicted in steps of this length, s.
inline constexpr double kDwaPredictionStep = 0.1;
/// DWA: the dynamic window holds the velocities reachable within this control interval, s...
inline constexpr double kDwaControlInterval = 0.25;
/// ...at these accelerations (also the braking the admissibility test assumes), m/s² and rad/s².
inline constexpr double kDwaLinearAcceleration = 1.0;
inline constexpr double kDwaAngularAcceleration = 2.0;
/// DWA: samples of the window, linear × angular.
inline constexpr int kDwaLinearSamples = 7;
inline constexpr int kDwaAngularSamples = 15;
/// DWA: weights of the objective's heading, clearance and velocity terms (each normalised over the
/// window). The heading term is the progress towards the point kDwaTargetDistance along the path.
inline constexpr double kDwaHeadingWeight = 1.0;
inline constexpr double kDwaClearanceWeight = 0.2;
inline constexpr double kDwaVelocityWeight = 0.4;
/// DWA: clearances beyond this no longer score, m.
inline constexpr double kDwaClearanceCap = 1.0;
/// DWA: the progress term aims at the point this far along the path, m.
inline constexpr double kDwaTargetDistance = 1.5;
/// DWA and ORCA: the gap the robot keeps from walls and furniture beyond touching, m: the map they see
/// is a grid, the body the physics stops is not.
inline constexpr double kRobotWallMargin = 0.05;
/// DWA and ORCA: the gap the robot keeps from people beyond touching, m (the margin people keep from
/// robots, humans::kPersonalSpaceFromRobots)...
inline constexpr double kRobotPersonalSpace = humans::kPersonalSpaceFromRobots;
/// ...or, on its way to or in a place it shares with people (a cabin, a queue), this little: a person
/// standing is inside their disc, and one walking keeps their stride's reach from the robot
/// (humans::kLimbClearance); more would leave the robot no way into a cabin with three riders.
inline constexpr double kRobotPlaceClearance = 0.1;
/// ORCA and social force: the velocity they choose is safe in its own direction only, so the base turns
/// on the spot towards it when it points further away than this, rad.
inline constexpr double kPlannerTurnOnTheSpotAngle = 0.3;
/// ORCA: people considered, their number and range (m), and the horizons for people and for walls (s).
inline constexpr int kOrcaRobotNeighbours = 10;
inline constexpr double kOrcaRobotNeighbourDistance = 3.0;
inline constexpr double kOrcaRobotTimeHorizon = 2.0;
inline constexpr double kOrcaRobotObstacleHorizon = 1.0;
/// ORCA: walls are seen as the nearest obstacle point in each of this many directions round the robot.
inline constexpr int kOrcaRobotObstacleSectors = 8;

/// Social force: the weight of the driving force and the obstacle force's decay length (m) HuNavSim's
/// lightsfm gives its agents; the other parameters are those people have (humans::SocialForceParams).
inline constexpr double kSocialForceRobotDesiredFactor = 2.0;
inline constexpr double kSocialForceRobotObstacleSigma = 0.2;
/// The social force robot's parameters: Moussaïd's interaction as people have it, with lightsfm's
/// driving and obstacle terms.
humans::SocialForceParams social_force_robot_params();

/// A person as the planners see them.
struct Person {
  Vec2 position = Vec2::Zero();
  Vec2 velocity = Vec2::Zero();
  double radius = 0.0;
};

/// What is around the robot this tick: the people, and the static obstacles (map, closed doors) as the
/// nearest obstacle point to a place within a range.
struct Surroundings {
  std::span<const Person> people;
  humans::ObstacleQuery nearest_obstacle;
  double obstacle_inset = 0.0;  ///< m: an obstacle point lies this far inside the obstacle's surface
  double personal_space = kRobotPersonalSpace;  ///< m: the gap to keep from people beyond touching
};

/// The robot as the planners see it.
struct RobotMotion {
  Pose2 pose;
  Twist twist;  ///< what the base does now
  double radius = 0.0;
  DifferentialDriveParams limits;
};

/// DWA: the admissible (v, ω) of the dynamic window with the best objective; when none is admissible,
/// turning on the spot towards the path.
Twist dynamic_window(const RobotMotion& robot, const std::vector<Vec2>& path, double speed, const Surroundings& around);

/// ORCA: the velocity closest to the path's that leaves no collision with any person (who is assumed not
/// to avoid) within kOrcaRobotTimeHorizon, nor with the nearest obstacle within kOrcaRobotObstacleHorizon.
Vec2 orca_velocity(const RobotMotion& robot, const std::vector<Vec2>& path, double speed, const Surroundings& around,
                   double dt);

/// Social force: the robot's velocity after one tick under the driving force towards the path and the
/// people's and the nearest obstacle's repulsion.
Vec2 social_force_velocity(const RobotMotion& robot, const std::vector<Vec2>& path, double speed,
                           const Surroundings& around, double dt);

}  // namespace hrisim::robots
