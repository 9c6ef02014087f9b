#pragma once
// What several tasks share: checking an action, the robot's frame, its drive and arm.
#include <string>
#include <vector>

#include "tasks/task.hpp"

namespace hrisim::tasks {

/// Throws core::Error(bad_request) naming the value that is wrong (pointer "/action" or "/action/i")
/// for a wrong length or a value that is not finite.
void check_action(const std::vector<double>& action, std::size_t size);

/// The robot's motion as both navigation observations begin: x, y (map frame), cos θ, sin θ, forward
/// speed, yaw rate (0 for a robot without a model).
std::vector<double> robot_motion(const sim::Session& session, int robot);
/// Appends the bounds of robot_motion's values (the map's extent, ±1, the speed and turn limits) to
/// low and high; returns the map's diagonal, m.
double add_robot_motion_bounds(const scenario::Model& model, double max_speed, double max_turn, std::vector<double>& low,
                               std::vector<double>& high);

/// The robot's runtime (a robot with a model); throws core::Error(conflict) for another agent.
const sim::RobotRuntime& runtime_of(const sim::Session& session, int agent);

/// The wheel action of a robot with a drive: forward speed and yaw rate within its limits.
Space drive_action_space(const scenario::AgentDef& robot);
/// Commands the wheels: the action clipped to `space`.
void drive(sim::Session& session, int robot, const std::vector<double>& action, const Space& space);

/// Appends the joint limits of the robot's "arm" group, in its order (±π for an unbounded joint).
void add_arm_limits(const scenario::AgentDef& robot, std::vector<double>& low, std::vector<double>& high);
/// Arm position targets: `action[first..]` clipped to the limits.
void command_arm(sim::Session& session, int robot, const std::vector<double>& action, std::size_t first, const Space& space);
/// Positions of the arm group's joints now.
std::vector<double> arm_positions(const sim::Session& session, int robot);

/// A reward of these terms, their sum as its total.
Reward sum_of(std::vector<std::pair<std::string, double>> terms);

/// The value of the reward term named `name` among `terms`; 0 when there is none.
double term(const std::vector<std::pair<std::string, double>>& terms, const std::string& name);

/// Counts, over a step's ticks, the penalised obstacles and objects the robot touches (in the task's
/// state: TaskState::touched_this_step).
class TouchCounter {
 public:
  explicit TouchCounter(const scenario::TaskSettings& task);
  void after_tick(sim::Session& session) const;
  /// Ends the step's count: the names touched during it, sorted, become the last step's
  /// (TaskState::touched_last_step, returned); the next step counts afresh.
  const std::vector<std::string>& end_step(sim::Session& session) const;

 private:
  int robot_;
  std::vector<std::string> penalised_;  ///< sorted
};

}  // namespace hrisim::tasks
