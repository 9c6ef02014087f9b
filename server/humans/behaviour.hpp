#pragma once
// How a person reacts to a robot that comes into view: HuNavSim's behaviours (Pérez-Higueras et al.
// 2023, robotics-upo/hunav_sim, hunav_agent_manager: the behaviour trees BT<X>Nav.xml and
// AgentManager's lookAtTheRobot, approximateRobot, avoidRobot and blockRobot). Every number is
// HuNavSim's default configuration; docs/behaviours.md gives each one's source.
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string_view>
#include <tuple>

namespace hrisim::humans {

enum class BehaviourType { regular, impassive, surprised, scared, curious, threatening };

std::string_view behaviour_name(BehaviourType type);
std::optional<BehaviourType> behaviour_type(std::string_view name);

/// A robot is in view within the detection distance and this far either side of where the person
/// faces, rad (HuNavSim's isRobotVisible: π/2 + 0.17).
inline constexpr double kBehaviourFieldOfView = 1.5708 + 0.17;
/// A reaction under way ends once the robot is this far beyond the detection distance, m (HuNavSim
/// has no margin: at the boundary its people would start and stop every tick).
inline constexpr double kReactionReleaseMargin = 0.5;
/// Curious: the approach slows with the distance to the robot over this range, m (max_dist_view_).
inline constexpr double kCuriousViewRange = 10.0;
/// Scared: the push away from the robot is factor × kScaredForceSigma / surface distance, m
/// (lightsfm's forceSigmaObstacle), beside a pull to the person's way of kScaredGoalFactor.
inline constexpr double kScaredForceSigma = 0.2;
inline constexpr double kScaredGoalFactor = 2.0;
/// Threatening: within this of the spot in front of the robot, the person turns to face it, m.
inline constexpr double kThreateningFaceDistance = 0.6;

/// A person's behaviour and its settings. `distance` means, by type: where the curious one stops from
/// the robot (centre to centre), how far in front of it the threatening one stands; `speed` is the
/// scared one's running-away speed, the curious one's top approach speed (0: the person's own top
/// speed) and the threatening one's; `force_factor` weighs the scared one's push away.
struct Behaviour {
  BehaviourType type = BehaviourType::regular;
  double detection_distance = 0.0;  ///< m; 0: never reacts
  double duration = 0.0;            ///< s of the robot in view that one reaction lasts
  bool once = true;                 ///< react only the first time
  double speed = 0.0;               ///< m/s
  double distance = 0.0;            ///< m
  double force_factor = 0.0;

  auto fields() const { return std::tie(type, detection_distance, duration, once, speed, distance, force_factor); }
};

/// HuNavSim's defaults for a type (hunav_loader.cpp's default configuration and the trees' values).
Behaviour default_behaviour(BehaviourType type);

/// A scenario's `behaviour` (checked against the schema): a name takes the defaults for it, an object
/// overrides any of them.
Behaviour read_behaviour(const nlohmann::json& entry);

}  // namespace hrisim::humans
