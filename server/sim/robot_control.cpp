#include "sim/robot_control.hpp"

#include <cmath>

#include "robots/controllers.hpp"
#include "robots/local_planners.hpp"
#include "sim/events.hpp"
#include "sim/search.hpp"
#include "sim/walking.hpp"

namespace hrisim::sim {

namespace {

using Kind = scenario::RobotController::Kind;

/// The base command of a robot following `path` with its controller's law.
robots::Twist follow_path(const scenario::Model& model, const State& state, const RobotRuntime& runtime, const std::vector<Vec2>& path) {
  const AgentState& self = state.agents[runtime.agent];
  const Pose2 pose = runtime.robot.pose();
  const double speed = self.preferred_speed;
  if (runtime.controller.kind == Kind::goal || runtime.controller.kind == Kind::idle) return robots::pure_pursuit(pose, path, speed);
  std::vector<robots::Person> people;
  for (std::size_t other = 0; other < state.agents.size(); ++other) {
    const AgentState& person = state.agents[other];
    if (person.active && model.agents[other].kind == scenario::AgentKind::human) people.push_back({person.position, person.velocity, model.agents[other].radius});
  }
  const robots::Surroundings around{people, [&model, &state](const Vec2& p, double range) { return nearest_obstacle(model, state, p, range); },
                                    model.grid.resolution() / 2.0,
                                    self.reservation.space.valid() ? robots::kRobotPlaceClearance : robots::kRobotPersonalSpace};
  const robots::RobotMotion motion{pose, runtime.robot.twist(), model.agents[runtime.agent].radius, runtime.robot.description().drive->params};
  switch (runtime.controller.kind) {
    case Kind::social: {
      std::vector<Vec2> positions;
      for (const robots::Person& person : people) positions.push_back(person.position);
      return robots::follow_velocity(pose, robots::social_velocity(pose, path, speed, positions, motion.radius));
    }
    case Kind::dwa:
    case Kind::search: return robots::dynamic_window(motion, path, speed, around);
    case Kind::orca: return robots::follow_velocity(pose, robots::orca_velocity(motion, path, speed, around, model.dt), robots::kPlannerTurnOnTheSpotAngle);
    case Kind::social_force:
      return robots::follow_velocity(pose, robots::social_force_velocity(motion, path, speed, around, model.dt), robots::kPlannerTurnOnTheSpotAngle);
    default: return robots::pure_pursuit(pose, path, speed);
  }
}

}  // namespace

void decide_robots(const scenario::Model& model, State& state) {
  for (RobotRuntime& runtime : state.robots) {
    if (!runtime.robot.description().drive || !state.agents[runtime.agent].active) continue;
    const AgentState& self = state.agents[runtime.agent];
    const Pose2 pose = runtime.robot.pose();
    robots::Twist command = runtime.command;  // teleoperation, or an external controller
    const std::optional<robots::Twist> searching = runtime.controller.kind == Kind::search ? search_command(model, state, runtime) : std::nullopt;
    if (searching) {
      command = *searching;
    } else if (runtime.controller.kind == Kind::teleop) {
      // Under external control: its commands drive the robot, even along a choreography's goto.
    } else if (self.navigation.under_way && !self.navigation.path.empty()) {
      command = follow_path(model, state, runtime, std::vector<Vec2>(self.navigation.path.begin() + static_cast<std::ptrdiff_t>(self.navigation.path_index), self.navigation.path.end()));
    } else if (self.attitude.target_heading) {
      // Turning on the spot to a goal's heading or to look at something.
      command = {0.0, robots::kHeadingGain * core::wrap_angle(*self.attitude.target_heading - pose.theta)};
    } else {
      command = {};
    }
    runtime.robot.command_base(command);
  }
}

void move_robots(const scenario::Model& model, State& state, PhysicsBodies& physics) {
  for (std::size_t r = 0; r < state.robots.size(); ++r) {
    RobotRuntime& runtime = state.robots[r];
    AgentState& self = state.agents[runtime.agent];
    if (!self.active) continue;
    const bool was_navigating = self.navigation.under_way;
    const robots::Configuration before = runtime.robot.configuration();
    runtime.robot.step(runtime.motor_random);
    const double share = free_share(physics, r, runtime.robot, before);
    if (share < 1.0) runtime.robot.stop_at(before, share);
    if (runtime.held_object >= 0) runtime.robot.stop_gripper_at(runtime.grip_position);
    const Pose2& pose = runtime.robot.pose();
    self.position = pose.position();
    self.heading = pose.theta;
    self.velocity = core::heading_vector(pose.theta) * runtime.robot.twist().linear;
    if (self.attitude.target_heading && std::abs(core::wrap_angle(*self.attitude.target_heading - pose.theta)) <= kHeadingTolerance) self.attitude.target_heading.reset();
    if (was_navigating && runtime.controller.goal && (self.navigation.goal - self.position).norm() <= self.navigation.goal_radius &&
        (*runtime.controller.goal).position() == self.navigation.goal) {
      emit(model, state, model.agents[runtime.agent].id, events::RobotGoalReached{self.position.x(), self.position.y()});
    }
  }
}

}  // namespace hrisim::sim
