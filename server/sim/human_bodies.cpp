#include "sim/human_bodies.hpp"

#include "sim/events.hpp"

namespace hrisim::sim {

humans::Activity activity_of(const scenario::Model& model, const State& state, int agent) {
  const AgentState& self = state.agents[agent];
  humans::Activity activity;
  activity.time = time_of(model, state);
  activity.gait_distance = self.animation.gait_distance;
  activity.speed = self.velocity.norm();
  activity.turn_rate = self.animation.turn_rate;
  activity.motion = self.animation.motion;
  if (self.animation.motion) {
    const std::int64_t until = self.animation.motion_released_tick >= 0 ? self.animation.motion_released_tick : state.tick;
    activity.motion_time = static_cast<double>(until - self.animation.motion_tick) * model.dt;
    if (self.animation.motion_released_tick >= 0) activity.since_release = static_cast<double>(state.tick - self.animation.motion_released_tick) * model.dt;
  }
  return activity;
}

HumanBodies::HumanBodies(const scenario::Model& model) : cache_(model.agents.size()) {
  for (const scenario::AgentDef& def : model.agents) {
    skeletons_.push_back(def.kind == scenario::AgentKind::human
                             ? std::optional(humans::Skeleton(humans::body_dimensions(def.type).value_or(humans::kAdultBody)))
                             : std::nullopt);
  }
}

const humans::BodyCapsules& HumanBodies::of(const scenario::Model& model, const State& state, int agent) const {
  const AgentState& self = state.agents[agent];
  // The physics world, each laser scan and each camera ask for the same bodies within a tick.
  Cached& cached = cache_[agent];
  if (cached.tick == state.tick && cached.position == self.position && cached.heading == self.heading) return cached.body;
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.translation() = Eigen::Vector3d(self.position.x(), self.position.y(), 0.0);
  base.linear() = Eigen::AngleAxisd(self.heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const humans::Skeleton& skeleton = *skeletons_[agent];
  cached = {state.tick, self.position, self.heading,
            humans::body_capsules(skeleton, humans::forward_kinematics(skeleton, humans::body_pose(activity_of(model, state, agent)), base))};
  return cached.body;
}

}  // namespace hrisim::sim
