#include "tasks/environment.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace hrisim::tasks {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

Space box(std::vector<double> low, std::vector<double> high) {
  Space space;
  space.name = "Box";
  space.shape = {static_cast<int>(low.size())};
  space.low = std::move(low);
  space.high = std::move(high);
  return space;
}

}  // namespace

Environment::Environment(const sim::Session& session) {
  const scenario::Model& model = session.model();
  for (std::size_t a = 0; a < model.agents.size() && robot_ < 0; ++a) {
    if (model.agents[a].kind == scenario::AgentKind::robot) robot_ = static_cast<int>(a);
  }
  if (robot_ < 0) throw core::Error(core::ErrorCode::conflict, "scenario '" + model.name + "' has no robot to observe or act");
  const scenario::AgentDef& robot = model.agents[robot_];
  drive_ = robot.robot_model && robot.robot_model->drive;
  if (robot.robot_model && !drive_) {
    throw core::Error(core::ErrorCode::conflict, "robot '" + robot.id + "' has no drive: it has no navigation action");
  }

  const world::OccupancyGrid& grid = model.grid;
  const double x0 = grid.origin().x(), y0 = grid.origin().y();
  const double x1 = x0 + grid.width() * grid.resolution(), y1 = y0 + grid.height() * grid.resolution();
  const double diagonal = std::hypot(x1 - x0, y1 - y0);
  const double max_speed = drive_ ? robot.robot_model->drive->params.max_linear_speed : kDiscRobotMaxSpeed;
  const double max_turn = drive_ ? robot.robot_model->drive->params.max_angular_speed : kInfinity;
  std::vector<double> low{x0, y0, -1, -1, -max_speed, -max_turn, -diagonal, -diagonal};
  std::vector<double> high{x1, y1, 1, 1, max_speed, max_turn, diagonal, diagonal};
  for (int p = 0; p < kObservedPeople; ++p) {
    low.insert(low.end(), {0, -kObservationRange, -kObservationRange, -kInfinity, -kInfinity});
    high.insert(high.end(), {1, kObservationRange, kObservationRange, kInfinity, kInfinity});
  }
  observation_space_ = box(std::move(low), std::move(high));
  action_space_ = drive_ ? box({-max_speed, -max_turn}, {max_speed, max_turn}) : box({-max_speed, -max_speed}, {max_speed, max_speed});
}

std::vector<double> Environment::observe(const sim::Session& session) const {
  const scenario::Model& model = session.model();
  const sim::AgentState& robot = session.state().agents[robot_];
  const double c = std::cos(robot.heading), s = std::sin(robot.heading);
  // Map-frame vector into the robot's frame (x ahead, y left).
  const auto local = [&](const core::Vec2& v) { return core::Vec2(c * v.x() + s * v.y(), -s * v.x() + c * v.y()); };
  double yaw_rate = 0.0;
  if (const sim::RobotRuntime* runtime = session.robot_runtime(session.agent_id(model.agents[robot_].id))) {
    yaw_rate = runtime->robot.twist().angular;
  }
  std::vector<double> observation{robot.position.x(), robot.position.y(), c, s, robot.velocity.dot(core::Vec2(c, s)), yaw_rate, 0, 0};
  const scenario::RobotController& controller = model.agents[robot_].controller;
  if (controller.goal) {
    const core::Vec2 goal = local(controller.goal->position() - robot.position);
    observation[6] = goal.x();
    observation[7] = goal.y();
  }
  std::vector<std::pair<double, int>> people;
  for (std::size_t a = 0; a < model.agents.size(); ++a) {
    const sim::AgentState& agent = session.state().agents[a];
    if (model.agents[a].kind != scenario::AgentKind::human || !agent.active) continue;
    const double distance = (agent.position - robot.position).norm();
    if (distance <= kObservationRange) people.emplace_back(distance, static_cast<int>(a));
  }
  std::sort(people.begin(), people.end());  // ties by agent index
  for (int p = 0; p < kObservedPeople; ++p) {
    if (p >= static_cast<int>(people.size())) {
      observation.insert(observation.end(), kPersonValues, 0.0);
      continue;
    }
    const sim::AgentState& person = session.state().agents[people[p].second];
    const core::Vec2 at = local(person.position - robot.position), moving = local(person.velocity);
    observation.insert(observation.end(), {1.0, at.x(), at.y(), moving.x(), moving.y()});
  }
  return observation;
}

void Environment::act(sim::Session& session, const std::vector<double>& action) const {
  if (action.size() != 2) {
    throw core::Error(core::ErrorCode::bad_request, "action: expected 2 values, got " + std::to_string(action.size()), {{"pointer", "/action"}});
  }
  for (std::size_t i = 0; i < action.size(); ++i) {
    if (!std::isfinite(action[i])) {
      throw core::Error(core::ErrorCode::bad_request, "action: every value must be a finite number", {{"pointer", "/action/" + std::to_string(i)}});
    }
  }
  const sim::AgentId id = session.agent_id(session.model().agents[robot_].id);
  const double a = std::clamp(action[0], action_space_.low[0], action_space_.high[0]);
  const double b = std::clamp(action[1], action_space_.low[1], action_space_.high[1]);
  if (drive_) {
    session.command_robot_twist(id, {a, b});
  } else {
    session.command_robot(id, {a, b});
  }
}

double Environment::reward(const sim::Session&) const { return 0.0; }

}  // namespace hrisim::tasks
