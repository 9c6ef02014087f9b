#include "tasks/environment.hpp"

#include "core/error.hpp"
#include "tasks/manipulation.hpp"
#include "tasks/navigation.hpp"
#include "tasks/task_support.hpp"

namespace hrisim::tasks {

std::shared_ptr<const Task> make_task(const sim::Session& session) {
  const auto& task = session.model().task;
  if (!task) return std::make_shared<const DefaultTask>(session);
  switch (task->kind) {
    case scenario::TaskKind::approach_human:
    case scenario::TaskKind::follow_human:
    case scenario::TaskKind::approach_human_apartment:
      return std::make_shared<const NavigationTask>(session);
    case scenario::TaskKind::pick_and_place:
      return std::make_shared<const PickAndPlace>(session);
    case scenario::TaskKind::mirror_gesture:
      return std::make_shared<const MirrorGesture>(session);
  }
  throw core::Error(core::ErrorCode::internal, "unknown task");
}

Environment::Environment(sim::Session& session) : task_(make_task(session)) {
  task_->begin(session);
  session.task_state().terminated = task_->terminated(session);
}

int Environment::begin_step(sim::Session& session, const std::optional<std::vector<double>>& action) const {
  if (!action) {
    task_->before_step(session);
    return task_->idle_ticks(session);
  }
  check_action(*action, static_cast<std::size_t>(action_space().shape.at(0)));
  const int ticks = task_->act(session, *action);
  task_->before_step(session);
  return ticks;
}

Reward Environment::end_step(sim::Session& session) const {
  Reward reward = task_->reward(session);
  sim::TaskState& state = session.task_state();
  state.last_reward_terms = reward.terms;
  state.terminated = task_->terminated(session);
  return reward;
}

}  // namespace hrisim::tasks
