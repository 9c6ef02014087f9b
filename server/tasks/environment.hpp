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

class Environment {
 public:
  /// Sets the episode up on a fresh session (the human's random place, gesture or walking style,
  /// drawn from the session's seed). Throws core::Error(conflict) when the scenario has no robot that
  /// can act.
  explicit Environment(sim::Session& session);
  /// The same environment as it is now (its task's bookkeeping), for a copy of its episode.
  Environment(const Environment& other) : task_(other.task_->clone()), terminated_(other.terminated_) {}
  Environment& operator=(const Environment&) = delete;

  const Space& observation_space() const { return task_->observation_space(); }
  const Space& action_space() const { return task_->action_space(); }
  /// The camera image that is the observation, when it is one; observe() is then empty.
  const std::optional<ImageObservation>& image() const { return task_->image(); }
  std::vector<double> observe(const sim::Session& session) const { return task_->observe(session); }

  /// Starts an env step: gives `action` (when there is one) and returns the ticks the step lasts (the
  /// task's frame skip). Throws core::Error(bad_request) naming the value that is wrong (pointer
  /// "/action/i") for a wrong length or a value that is not finite; values out of bounds are clipped.
  int begin_step(sim::Session& session, const std::optional<std::vector<double>>& action);
  /// After every tick of a step (e.g. counting the obstacles touched).
  void after_tick(const sim::Session& session) { task_->after_tick(session); }
  /// Ends a step once its ticks are done (or the session finished): its reward, and the task's ending.
  Reward end_step(const sim::Session& session);
  /// Ticks a step without a new action lasts: the frame skip (pick_and_place: its last step's).
  int step_ticks() const { return task_->idle_ticks(); }
  /// The task's ending (e.g. the robot reached the human); the time limit truncates instead.
  bool terminated() const { return terminated_; }
  /// The last step's reward terms and measures.
  nlohmann::json info() const { return task_->info(); }

 private:
  std::unique_ptr<Task> task_;
  bool terminated_ = false;
};

}  // namespace hrisim::tasks
