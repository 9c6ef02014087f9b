#include "sim/robot_control.hpp"

#include <cmath>

#include "robots/controllers.hpp"
#include "sim/events.hpp"
#include "sim/walking.hpp"

namespace hrisim::sim {

void decide_robots(const scenario::Model& model, State& state) {
  for (RobotRuntime& runtime : state.robots) {
    if (!runtime.robot.description().drive || !state.agents[runtime.agent].active) continue;
    const AgentState& self = state.agents[runtime.agent];
    const Pose2 pose = runtime.robot.pose();
    robots::Twist command = runtime.command;  // teleoperation, or an external controller
    if (runtime.controller.kind == scenario::RobotController::Kind::teleop) {
      // Under external control: its commands drive the robot, even along a choreography's goto.
    } else if (self.navigating && !self.path.empty()) {
      const std::vector<Vec2> path(self.path.begin() + static_cast<std::ptrdiff_t>(self.path_index), self.path.end());
      if (runtime.controller.kind == scenario::RobotController::Kind::social) {
        std::vector<Vec2> people;
        for (std::size_t other = 0; other < state.agents.size(); ++other) {
          if (state.agents[other].active && model.agents[other].kind == scenario::AgentKind::human) people.push_back(state.agents[other].position);
        }
        command = robots::follow_velocity(pose, robots::social_velocity(pose, path, self.preferred_speed, people, model.agents[runtime.agent].radius));
      } else {
        command = robots::pure_pursuit(pose, path, self.preferred_speed);
      }
    } else if (self.target_heading) {
      // Turning on the spot to a goal's heading or to look at something.
      command = {0.0, robots::kHeadingGain * core::wrap_angle(*self.target_heading - pose.theta)};
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
    const bool was_navigating = self.navigating;
    const robots::Configuration before = runtime.robot.configuration();
    runtime.robot.step(runtime.motor_random);
    const double share = free_share(physics, r, runtime.robot, before);
    if (share < 1.0) runtime.robot.stop_at(before, share);
    const Pose2& pose = runtime.robot.pose();
    self.position = pose.position();
    self.heading = pose.theta;
    self.velocity = core::heading_vector(pose.theta) * runtime.robot.twist().linear;
    if (self.target_heading && std::abs(core::wrap_angle(*self.target_heading - pose.theta)) <= kHeadingTolerance) self.target_heading.reset();
    if (was_navigating && runtime.controller.goal && (self.goal - self.position).norm() <= self.goal_radius &&
        (*runtime.controller.goal).position() == self.goal) {
      emit(model, state, "robot_goal_reached", model.agents[runtime.agent].id, {{"x", self.position.x()}, {"y", self.position.y()}});
    }
  }
}

}  // namespace hrisim::sim
