#include "sim/carrying.hpp"

#include <algorithm>
#include <string>

#include "robots/robot.hpp"
#include "scenario/reaching.hpp"
#include "sim/choreography.hpp"
#include "sim/events.hpp"
#include "sim/walking.hpp"

namespace hrisim::sim {
namespace {

using Kind = scenario::Action::Kind;

/// Half the object's height as it stands upright, m.
double half_height(const robots::Shape& shape) {
  switch (shape.kind) {
    case robots::Shape::Kind::box:
      return 0.5 * shape.size.z();
    case robots::Shape::Kind::cylinder:
      return 0.5 * shape.length;
    case robots::Shape::Kind::capsule:
      return 0.5 * shape.length + shape.radius;
    case robots::Shape::Kind::sphere:
      return shape.radius;
  }
  return 0.0;
}

/// Upright as it was placed in the scenario, turned about z by `yaw`, at `centre`.
Eigen::Isometry3d upright(const scenario::MovableObject& object, double yaw, const Eigen::Vector3d& centre) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = centre;
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * robots::to_isometry(object.pose).linear();
  return pose;
}

bool held_by_someone_else(const State& state, int agent, int object) {
  for (std::size_t a = 0; a < state.agents.size(); ++a) {
    if (static_cast<int>(a) != agent && state.agents[a].active && state.agents[a].carrying.object.value == object) return true;
  }
  return std::any_of(state.robots.begin(), state.robots.end(), [&](const RobotRuntime& robot) { return robot.held_object == object; });
}

void skip(const scenario::Model& model, State& state, int agent, const scenario::Action& action, const std::string& reason) {
  if (action.kind == Kind::pick_up) {
    emit(model, state, model.agents[agent].id, events::PickUpSkipped{reason});
  } else {
    emit(model, state, model.agents[agent].id, events::PutDownSkipped{reason});
  }
  state.agents[agent].carrying.phase = ReachPhase::done;
}

Vec2 item_position(const State& state, const scenario::Action& action) {
  return action.kind == Kind::pick_up ? Vec2(state.objects[action.target].pose.translation().head<2>()) : action.pose.position();
}

}  // namespace

bool start_reaching(const scenario::Model& model, State& state, int agent, const scenario::Action& action) {
  AgentState& self = state.agents[agent];
  const bool pick = action.kind == Kind::pick_up;
  if (pick && self.carrying.object.value == action.target) {
    skip(model, state, agent, action, "already carrying " + model.objects[action.target].name);
    return true;
  }
  if (pick && held_by_someone_else(state, agent, action.target)) return false;
  if (pick && self.carrying.object.valid()) {
    skip(model, state, agent, action, "hands full: carrying " + model.objects[self.carrying.object.value].name);
    return true;
  }
  if (!pick && !self.carrying.object.valid()) {
    skip(model, state, agent, action, "carrying nothing");
    return true;
  }
  const Vec2 item = item_position(state, action);
  const std::optional<Vec2> spot = scenario::reach_spot(model, item, self.position, model.agents[agent].radius);
  if (!spot) {
    skip(model, state, agent, action, "no free spot within " + core::number_text(scenario::kMaxHandReach) + " m of (" + core::point_text(item) + ")");
    return true;
  }
  release_reservations(state, agent);
  self.carrying.phase = ReachPhase::walking;
  go_to(model, state, agent, {spot->x(), spot->y(), scenario::reach_heading(*spot, item)}, scenario::kReachSpotRadius, true);
  return true;
}

void tend_reaching(const scenario::Model& model, State& state, int agent, const scenario::Action& action) {
  AgentState& self = state.agents[agent];
  const bool pick = action.kind == Kind::pick_up;
  if (pick && self.carrying.object.value != action.target && self.carrying.phase != ReachPhase::done &&
      (held_by_someone_else(state, agent, action.target) ||
       (self.carrying.phase == ReachPhase::reaching && (item_position(state, action) - self.position).norm() > scenario::kMaxHandReach))) {
    // Taken by someone else, or moved out of reach, before the hand got there: start over.
    self.navigation.under_way = false;
    self.navigation.path.clear();
    self.carrying.phase = ReachPhase::none;
    return;
  }
  if (self.carrying.phase == ReachPhase::walking && !self.navigation.under_way && !self.attitude.target_heading) {
    self.carrying.phase = ReachPhase::reaching;
    self.animation.motion = humans::builtin_motion("reach");
    self.animation.motion_tick = state.tick;
    self.animation.motion_released_tick = -1;
    return;
  }
  if (self.carrying.phase != ReachPhase::reaching) return;
  const double played = static_cast<double>(state.tick - self.animation.motion_tick) * model.dt;
  const std::string& id = model.agents[agent].id;
  if (played >= kReachGraspTime && pick && self.carrying.object.value != action.target) {
    self.carrying.object = ObjectIndex(action.target);
    emit(model, state, id, events::PickedUp{model.objects[action.target].name});
  } else if (played >= kReachGraspTime && !pick && self.carrying.object.valid()) {
    const scenario::MovableObject& object = model.objects[self.carrying.object.value];
    const double z = action.value + half_height(object.shape) + kPutDownClearance;
    state.objects[self.carrying.object.value] = ObjectState{upright(object, self.heading, {action.pose.x, action.pose.y, z})};
    emit(model, state, id, events::PutDown{object.name, action.pose.x, action.pose.y});
    self.carrying.object = {};
  }
  if (played >= humans::builtin_motion("reach")->duration()) self.carrying.phase = ReachPhase::done;
}

bool reaching_done(const State& state, int agent) { return state.agents[agent].carrying.phase == ReachPhase::done; }

Eigen::Isometry3d carried_pose(const scenario::Model& model, const State& state, const HumanBodies& bodies, int agent) {
  const humans::Capsule& forearm = bodies.of(model, state, agent)[static_cast<int>(humans::BodyPart::r_forearm)];
  const Eigen::Vector3d along = (forearm.to - forearm.from).normalized();
  const AgentState& self = state.agents[agent];
  return upright(model.objects[self.carrying.object.value], self.heading, forearm.to + along * kGripOffset);
}

}  // namespace hrisim::sim
