#include "sim/behaviours.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/events.hpp"
#include "sim/walking.hpp"

namespace hrisim::sim {
namespace {

using humans::BehaviourType;

/// The nearest robot the person sees: within the detection distance, within the field of view of
/// where they face, and not behind a wall. The robot they already react to they keep in mind without
/// facing it, until it is kReactionReleaseMargin beyond the detection distance.
int robot_in_view(const scenario::Model& model, const State& state, int agent) {
  const AgentState& self = state.agents[agent];
  int nearest = -1;
  double nearest_distance = std::numeric_limits<double>::infinity();
  for (std::size_t r = 0; r < state.agents.size(); ++r) {
    const AgentState& robot = state.agents[r];
    if (model.agents[r].kind != scenario::AgentKind::robot || !robot.active) continue;
    const bool noticed = static_cast<int>(r) == self.reaction.reacting_to.value;
    const double distance = (robot.position - self.position).norm();
    if (distance > self.reaction.behaviour.detection_distance + (noticed ? humans::kReactionReleaseMargin : 0.0) || distance >= nearest_distance) continue;
    const double bearing = core::wrap_angle(core::direction_to(self.position, robot.position) - self.heading);
    if ((!noticed && std::abs(bearing) > humans::kBehaviourFieldOfView) || !model.planner.line_of_sight(self.position, robot.position, 0.0)) continue;
    nearest = static_cast<int>(r);
    nearest_distance = distance;
  }
  return nearest;
}

void end_reaction(const scenario::Model& model, State& state, int agent, events::ReactionEnd why) {
  AgentState& self = state.agents[agent];
  if (!self.reaction.reacting_to.valid()) return;
  emit(model, state, model.agents[agent].id, events::ReactionEnded{self.reaction.behaviour.type, model.agents[self.reaction.reacting_to.value].id, why});
  self.reaction.reacting_to = {};
}

}  // namespace

Vec2 react_to_robots(const scenario::Model& model, State& state, int agent, const Vec2& preferred, std::optional<double>& watching_heading) {
  AgentState& self = state.agents[agent];
  const humans::Behaviour& behaviour = self.reaction.behaviour;
  if (behaviour.detection_distance <= 0.0 || self.reaction.behaviour_spent) return preferred;
  const int robot = robot_in_view(model, state, agent);
  if (robot < 0) {
    end_reaction(model, state, agent, events::ReactionEnd::out_of_view);  // the reaction's clock runs only while the robot is seen
    return preferred;
  }
  if (self.reaction.reacting_to.value != robot) {
    end_reaction(model, state, agent, events::ReactionEnd::another_robot);
    self.reaction.reacting_to = AgentIndex(robot);
    emit(model, state, model.agents[agent].id, events::ReactionStarted{behaviour.type, model.agents[robot].id});
  }
  self.reaction.behaviour_seen += model.dt;
  if (self.reaction.behaviour_seen >= behaviour.duration) {
    end_reaction(model, state, agent, events::ReactionEnd::duration);
    self.reaction.behaviour_seen = 0.0;
    self.reaction.behaviour_spent = behaviour.once;
    return preferred;
  }
  const AgentState& other = state.agents[robot];
  const Vec2 to_robot = other.position - self.position;
  const double distance = to_robot.norm();
  const Vec2 towards = distance > 1e-9 ? Vec2(to_robot / distance) : Vec2(core::heading_vector(self.heading));
  switch (behaviour.type) {
    case BehaviourType::regular:
    case BehaviourType::impassive:
      return preferred;
    case BehaviourType::surprised:
      watching_heading = core::direction_to(self.position, other.position);
      return Vec2::Zero();
    case BehaviourType::curious: {
      if (distance <= behaviour.distance) {
        watching_heading = core::direction_to(self.position, other.position);
        return Vec2::Zero();
      }
      const double top = behaviour.speed > 0.0 ? behaviour.speed : self.preferred_speed * humans::kMaxSpeedFactor;
      return towards * top * std::min(1.0, distance / humans::kCuriousViewRange);
    }
    case BehaviourType::scared: {
      const double gap = std::max(distance - model.agents[agent].radius - model.agents[robot].radius, 0.05);
      const Vec2 away = -towards * behaviour.force_factor * humans::kScaredForceSigma / gap;
      const Vec2 way = preferred.norm() > 1e-9 ? Vec2(preferred.normalized() * humans::kScaredGoalFactor) : Vec2::Zero();
      const Vec2 wanted = away + way;
      watching_heading = core::direction_to(self.position, other.position);  // backing away, eyes on it
      return wanted.norm() > 1e-9 ? Vec2(wanted.normalized() * behaviour.speed) : Vec2::Zero();
    }
    case BehaviourType::threatening: {
      const Vec2 spot = other.position + core::heading_vector(other.heading) * behaviour.distance;
      if ((spot - self.position).norm() <= humans::kThreateningFaceDistance) watching_heading = core::direction_to(self.position, other.position);
      return into_the_way(self, other, behaviour.distance, behaviour.speed);
    }
  }
  return preferred;
}

}  // namespace hrisim::sim
