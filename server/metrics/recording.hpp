#pragma once
// What an episode leaves behind for its metrics: the robot under test and every human at every step,
// and the events. Filled by the simulation (sim::EpisodeRecorder); metrics only read it.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/math.hpp"

namespace hrisim::metrics {

using core::Vec2;

/// A disc-shaped body at one step.
struct Body {
  int agent = -1;  ///< which agent of the scenario, stable across samples
  Vec2 position = Vec2::Zero();
  Vec2 velocity = Vec2::Zero();
  double heading = 0.0;
  double radius = 0.0;
  bool touching_robot = false;  ///< humans: the physics reports contact with the robot's body
};

struct Sample {
  std::int64_t tick = 0;
  Body robot;
  std::vector<Body> humans;  ///< the humans present at this step
  /// Surface distance from the robot to the nearest static obstacle (wall, furniture), m.
  double obstacle_distance = 0.0;
  /// Static things (walls "map", named obstacles and objects) the robot's body touches.
  std::vector<std::string> touched_obstacles;
  /// Agents of each group of two or more people at this step (indices into humans).
  std::vector<std::vector<int>> groups;
  /// The benchmark task's rewards of the env steps ended by this tick, summed (0 without a task).
  double reward = 0.0;
};

/// The events the metrics read: a robot's requests and their answers, and a search's find.
struct RecordedEvent {
  enum class Kind { request, request_accepted, request_dropped, person_found };
  std::int64_t tick = 0;
  Kind kind = Kind::request;
  std::optional<std::int64_t> request;  ///< request events: the request's id
};

struct Recording {
  double dt = 0.0;
  bool has_robot = false;  ///< false: the robot metrics are null
  std::optional<Vec2> goal;  ///< the robot's navigation goal, when it has one
  double goal_radius = 0.0;
  /// Length of the shortest collision-free path from the start to the goal on the map's grid inflated
  /// by the robot's radius, people ignored; empty without a goal or a path.
  std::optional<double> shortest_path_length;
  bool searching = false;  ///< the robot's controller searches for a person
  bool has_choreography = false;
  /// The choreography gives the robot something to do (a step's action, a request it makes): then its
  /// completion is the success of a robot without a goal or a search.
  bool robot_in_choreography = false;
  /// The scenario's benchmark task, when it has one: whether it ends at a goal condition
  /// (scenario::has_goal_condition), reached when the episode ends with termination "goal".
  std::optional<bool> task_goal_condition;
  bool choreography_completed = false;
  std::string termination;  ///< goal, collision, timeout, scenario_end, cancelled, error
  /// The benchmark task's summed reward; empty for a scenario without a benchmark task.
  std::optional<double> episode_reward;
  /// Each term of the task's reward (tasks::Reward), summed over the env steps; metric `reward_<name>`.
  std::vector<std::pair<std::string, double>> reward_terms;
  std::vector<Sample> samples;  ///< one per simulation step, the initial state first
  std::vector<RecordedEvent> events;
};

}  // namespace hrisim::metrics
