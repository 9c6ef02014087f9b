#pragma once
// A session as a Gymnasium environment for learning code: the scenario's benchmark task (seed 003 §4.4:
// approach_human, follow_human, approach_human_apartment, pick_and_place, mirror_gesture) or, without
// one, the default navigation task of its first robot (tasks/navigation.hpp). A step gives an action,
// lasts the task's ticks (its frame skip) and then measures the reward, as seed 003 §5.3 does. The
// episode (episode/episode.hpp) runs the ticks; the environment gives actions and measures.
#include <memory>
#include <optional>
#include <vector>

#include "tasks/task.hpp"

namespace hrisim::tasks {

/// The task's bookkeeping is in the session's state (sim::TaskState), so an environment is its task
/// alone: a copy of it shares the task, and goes on with a copy of the session (an episode made from
/// a checkpoint, whose session copy holds the task's state).
class Environment {
 public:
  /// Sets the episode up on a fresh session (the human's random place, gesture or walking style,
  /// drawn from the session's seed). Throws core::Error(conflict) when the scenario has no robot that
  /// can act.
  explicit Environment(sim::Session& session);

  const Space& observation_space() const { return task_->observation_space(); }
  const Space& action_space() const { return task_->action_space(); }
  /// The camera image that is the observation, when it is one; observe() is then empty.
  const std::optional<ImageObservation>& image() const { return task_->image(); }
  std::vector<double> observe(const sim::Session& session) const { return task_->observe(session); }

  /// Starts an env step: gives `action` (when there is one) and returns the ticks the step lasts (the
  /// task's frame skip). Throws core::Error(bad_request) naming the value that is wrong (pointer
  /// "/action/i") for a wrong length or a value that is not finite; values out of bounds are clipped.
  int begin_step(sim::Session& session, const std::optional<std::vector<double>>& action) const;
  /// After every tick of a step (e.g. counting the obstacles touched).
  void after_tick(sim::Session& session) const { task_->after_tick(session); }
  /// Ends a step once its ticks are done (or the session finished): its reward (its terms kept as the
  /// last step's), and the task's ending.
  Reward end_step(sim::Session& session) const;
  /// Ticks a step without a new action lasts: the frame skip (pick_and_place: its last step's).
  int step_ticks(const sim::Session& session) const { return task_->idle_ticks(session); }
  /// The task's ending (e.g. the robot reached the human); the time limit truncates instead.
  bool terminated(const sim::Session& session) const { return session.state().task.terminated; }
  /// The last step's reward terms and measures.
  nlohmann::json info(const sim::Session& session) const { return task_->info(session); }
  /// The task, configuration only: what an episode's copies share.
  const std::shared_ptr<const Task>& task() const { return task_; }

 private:
  std::shared_ptr<const Task> task_;
};

}  // namespace hrisim::tasks
