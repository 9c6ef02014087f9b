#pragma once
// The Gymnasium view of a session for learning code: what the robot under test (the scenario's first
// robot) observes, what it can do, and its reward. The default view is for navigation among people:
//
//   observation (float64, kObservationSize values)
//     [0, 1]  x, y of the robot in the map frame, m
//     [2, 3]  cos θ, sin θ of its heading
//     [4, 5]  forward speed v (m/s) and yaw rate ω (rad/s)
//     [6, 7]  its goal in the robot's frame (x ahead, y left), m; 0, 0 without a goal
//     then kObservedPeople blocks of 5, nearest person first, people within kObservationRange only:
//             present (1 or 0), position x, y in the robot's frame (m), velocity x, y in the robot's frame (m/s)
//   action (float64, 2 values): forward speed and yaw rate commanded to a robot with a drive (held until
//     the next action), clipped to its limits; for a robot without a model, its velocity in the map frame.
//   reward: 0 — the scenario defines no benchmark task (the benchmark tasks define theirs).
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "sim/session.hpp"

namespace hrisim::tasks {

/// People in the default observation, nearest first.
inline constexpr int kObservedPeople = 8;
/// People farther than this from the robot are left out of the observation, m.
inline constexpr double kObservationRange = 10.0;
/// Values per observed person: present, x, y, vx, vy.
inline constexpr int kPersonValues = 5;
inline constexpr int kObservationSize = 8 + kObservedPeople * kPersonValues;
/// Speed bound of a robot without a model in the action space, m/s.
inline constexpr double kDiscRobotMaxSpeed = 2.0;

/// A Gymnasium space: Box (shape, low, high, dtype) or Discrete (n).
struct Space {
  std::string name;  ///< "Box" or "Discrete"
  std::vector<int> shape;
  std::vector<double> low, high;  ///< may hold ±infinity
  std::string dtype = "float64";
  int n = 0;
};

/// The default navigation environment over a session.
class Environment {
 public:
  /// Throws core::Error(conflict) when the scenario has no robot to observe.
  explicit Environment(const sim::Session& session);

  const Space& observation_space() const { return observation_space_; }
  const Space& action_space() const { return action_space_; }
  std::vector<double> observe(const sim::Session& session) const;
  /// Gives the action to the robot; throws core::Error(bad_request) naming the value that is wrong
  /// (pointer "/action/i") for a wrong length or a value that is not finite. Values are clipped.
  void act(sim::Session& session, const std::vector<double>& action) const;
  /// Reward of the step that just happened.
  double reward(const sim::Session& session) const;

 private:
  int robot_ = -1;  ///< agent index of the robot under test
  bool drive_ = false;
  Space observation_space_, action_space_;
};

}  // namespace hrisim::tasks
