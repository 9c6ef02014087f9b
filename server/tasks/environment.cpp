#include "tasks/environment.hpp"

#include "core/error.hpp"
#include "tasks/manipulation.hpp"
#include "tasks/navigation.hpp"
#include "tasks/task_support.hpp"

namespace hrisim::tasks {

std::unique_ptr<View> make_view(const sim::Session& session) {
  const auto& task = session.model().task;
  if (!task) return std::make_unique<DefaultView>(session);
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

Environment::Environment(sim::Session& session) : view_(make_view(session)) {
  view_->begin(session);
  terminated_ = view_->terminated(session);
}

int Environment::begin_step(sim::Session& session, const std::optional<std::vector<double>>& action) {
  if (!action) {
    view_->before_step(session);
    return view_->idle_ticks();
  }
  check_action(*action, static_cast<std::size_t>(action_space().shape.at(0)));
  const int ticks = view_->act(session, *action);
  view_->before_step(session);
  return ticks;
}

Reward Environment::end_step(const sim::Session& session) {
  Reward reward = view_->reward(session);
  terminated_ = view_->terminated(session);
  return reward;
}

}  // namespace hrisim::tasks
