#pragma once
// A benchmark task: a Gymnasium environment's behaviour over a session — its spaces, what the robot
// under test observes and does, and an env step's reward and ending. Each task of seed 003 §4.4 is one;
// so is the default navigation task of scenarios that name none.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/session.hpp"

namespace hrisim::tasks {

/// A Gymnasium space: Box (shape, low, high, dtype) or Discrete (n). A Box's low and high hold one
/// value per element, or one value for all of them.
struct Space {
  std::string name;  ///< "Box" or "Discrete"
  std::vector<int> shape;
  std::vector<double> low, high;  ///< may hold ±infinity
  std::string dtype = "float64";
  int n = 0;
};

/// A Box space of one dimension with these bounds.
Space box(std::vector<double> low, std::vector<double> high);

/// The camera image observed instead of a vector (mirror_gesture): RGB-A and depth.
struct ImageObservation {
  std::string camera;  ///< ROBOT.SENSOR
  int width = 0, height = 0;
};

/// One env step's reward and its terms. Each term is also a metric of the episode, `reward_<name>`,
/// summed over its env steps (metrics/definitions.cpp lists them).
struct Reward {
  double total = 0.0;
  std::vector<std::pair<std::string, double>> terms;
};

/// A task is configuration only (the model's TaskSettings, its spaces): what its episode draws, counts
/// and measures is the session's (sim::TaskState, Session::task_state()), so one task serves an episode
/// and every copy of it.
class Task {
 public:
  virtual ~Task() = default;

  const Space& observation_space() const { return observation_space_; }
  const Space& action_space() const { return action_space_; }
  /// Set when the observation is a camera image; observe() is then empty.
  const std::optional<ImageObservation>& image() const { return image_; }

  /// Sets the episode up on a fresh session at tick 0 (draws from the session's seed only) and its
  /// part of the state (sim::TaskState::kind_state).
  virtual void begin(sim::Session& session) const { (void)session; }
  virtual std::vector<double> observe(const sim::Session& session) const = 0;
  /// Gives the action (already checked for length and finiteness); returns the ticks the step lasts.
  virtual int act(sim::Session& session, const std::vector<double>& action) const = 0;
  /// Called before each step's ticks, after its action (e.g. the human walks on).
  virtual void before_step(sim::Session& session) const { (void)session; }
  /// Ticks of a step without a new action.
  virtual int idle_ticks(const sim::Session& session) const = 0;
  /// Called after every tick of a step.
  virtual void after_tick(sim::Session& session) const { (void)session; }
  /// The step's reward, once its ticks are done; starts the next step's bookkeeping.
  virtual Reward reward(sim::Session& session) const = 0;
  virtual bool terminated(const sim::Session& session) const {
    (void)session;
    return false;
  }
  /// The last step's reward terms and measures, for Gymnasium's info: read from the task's state.
  virtual nlohmann::json info(const sim::Session& session) const {
    (void)session;
    return nlohmann::json::object();
  }

 protected:
  Space observation_space_, action_space_;
  std::optional<ImageObservation> image_;
};

/// The task a session's scenario names, or the default navigation task. Throws core::Error(conflict)
/// when the scenario has no robot that can act.
std::shared_ptr<const Task> make_task(const sim::Session& session);

}  // namespace hrisim::tasks
