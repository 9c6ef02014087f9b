#include "tasks/environment.hpp"

#include "core/error.hpp"
#include "tasks/manipulation.hpp"
#include "tasks/navigation.hpp"
#include "tasks/task_support.hpp"

namespace hrisim::tasks {

std::unique_ptr<Task> make_task(const sim::Session& session) {
  const auto& task = session.model().task;
  if (!task) return std::make_unique<DefaultTask>(session);
  switch (task->kind) {
    case scenario::TaskKind::approach_human:
    case scenario::TaskKind::follow_human:
    case scenario::TaskKind::approach_human_apartment:
      return std::make_unique<NavigationTask>(session);
    case scenario::TaskKind::pick_and_place:
      return std::make_unique<PickAndPlace>(session);
    case scenario::TaskKind::mirror_gesture:
      return std::make_unique<MirrorGesture>(session);
  }
  throw core::Error(core::ErrorCode::internal, "unknown task");
}

Environment::Environment(sim::Session& session) : task_(make_task(session)) {
  task_->begin(session);
  terminated_ = task_->terminated(session);
}

int Environment::begin_step(sim::Session& session, const std::optional<std::vector<double>>& action) {
  if (!action) {
    task_->before_step(session);
    return task_->idle_ticks();
  }
  check_action(*action, static_cast<std::size_t>(action_space().shape.at(0)));
  const int ticks = task_->act(session, *action);
  task_->before_step(session);
  return ticks;
}

Reward Environment::end_step(const sim::Session& session) {
  Reward reward = task_->reward(session);
  terminated_ = task_->terminated(session);
  return reward;
}

}  // namespace hrisim::tasks
