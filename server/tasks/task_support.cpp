#include "tasks/task_support.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace hrisim::tasks {

Space box(std::vector<double> low, std::vector<double> high) {
  Space space;
  space.name = "Box";
  space.shape = {static_cast<int>(low.size())};
  space.low = std::move(low);
  space.high = std::move(high);
  return space;
}

Reward sum_of(std::vector<std::pair<std::string, double>> terms) {
  Reward reward{0.0, std::move(terms)};
  for (const auto& term : reward.terms) reward.total += term.second;
  return reward;
}

double term(const std::vector<std::pair<std::string, double>>& terms, const std::string& name) {
  for (const auto& [known, value] : terms) {
    if (known == name) return value;
  }
  return 0.0;
}

void check_action(const std::vector<double>& action, std::size_t size) {
  if (action.size() != size) {
    throw core::Error(core::ErrorCode::bad_request,
                      "action: expected " + std::to_string(size) + " values, got " + std::to_string(action.size()), {{"pointer", "/action"}});
  }
  for (std::size_t i = 0; i < action.size(); ++i) {
    if (!std::isfinite(action[i])) {
      throw core::Error(core::ErrorCode::bad_request, "action: every value must be a finite number", {{"pointer", "/action/" + std::to_string(i)}});
    }
  }
}

std::vector<double> robot_motion(const sim::Session& session, int robot) {
  const sim::AgentState& state = session.state().agents[robot];
  const sim::RobotRuntime* runtime = session.robot_runtime(session.agent_at(robot));
  const core::Vec2 heading = core::heading_vector(state.heading);
  return {state.position.x(), state.position.y(), heading.x(), heading.y(), state.velocity.dot(heading),
          runtime ? runtime->robot.twist().angular : 0.0};
}

const sim::RobotRuntime& runtime_of(const sim::Session& session, int agent) {
  const sim::RobotRuntime* runtime = session.robot_runtime(session.agent_at(agent));
  if (!runtime) throw core::Error(core::ErrorCode::conflict, "agent '" + session.model().agents[agent].id + "' is not a robot with a model");
  return *runtime;
}

double add_robot_motion_bounds(const scenario::Model& model, double max_speed, double max_turn, std::vector<double>& low,
                               std::vector<double>& high) {
  const world::OccupancyGrid& grid = model.grid;
  const double x0 = grid.origin().x(), y0 = grid.origin().y();
  const double x1 = x0 + grid.width() * grid.resolution(), y1 = y0 + grid.height() * grid.resolution();
  low.insert(low.end(), {x0, y0, -1, -1, -max_speed, -max_turn});
  high.insert(high.end(), {x1, y1, 1, 1, max_speed, max_turn});
  return std::hypot(x1 - x0, y1 - y0);
}

Space drive_action_space(const scenario::AgentDef& robot) {
  const robots::DifferentialDriveParams& params = robot.robot_model->drive->params;
  return box({-params.max_linear_speed, -params.max_angular_speed}, {params.max_linear_speed, params.max_angular_speed});
}

void drive(sim::Session& session, int robot, const std::vector<double>& action, const Space& space) {
  const double v = std::clamp(action[0], space.low[0], space.high[0]);
  const double w = std::clamp(action[1], space.low[1], space.high[1]);
  session.command_robot_twist(session.agent_at(robot), {v, w});
}

void add_arm_limits(const scenario::AgentDef& robot, std::vector<double>& low, std::vector<double>& high) {
  const robots::RobotDescription& description = *robot.robot_model;
  for (const std::string& name : description.groups.at("arm")) {
    const robots::Joint& joint = description.joints[description.find_joint(name)];
    low.push_back(joint.limits.lower.value_or(-std::numbers::pi));
    high.push_back(joint.limits.upper.value_or(std::numbers::pi));
  }
}

void command_arm(sim::Session& session, int robot, const std::vector<double>& action, std::size_t first, const Space& space) {
  std::vector<double> targets;
  for (std::size_t i = first; i < action.size(); ++i) targets.push_back(std::clamp(action[i], space.low[i], space.high[i]));
  session.command_robot_joints(session.agent_at(robot), "arm", targets);
}

std::vector<double> arm_positions(const sim::Session& session, int robot) {
  const robots::Robot& body = runtime_of(session, robot).robot;
  std::vector<double> positions;
  for (const std::string& name : body.description().groups.at("arm")) positions.push_back(body.joint_position(body.joint_index(name)));
  return positions;
}

TouchCounter::TouchCounter(const scenario::TaskSettings& task) : robot_(task.robot), penalised_(task.penalised) {
  std::sort(penalised_.begin(), penalised_.end());
}

void TouchCounter::after_tick(sim::Session& session) const {
  const scenario::Model& model = session.model();
  std::vector<std::string>& touched = session.task_state().touched_this_step;
  for (const sim::Contact& contact : runtime_of(session, robot_).contacts) {
    if (contact.agent >= 0) continue;
    const std::string& name = contact.object >= 0 ? model.objects[contact.object].name : contact.part;
    if (!std::binary_search(penalised_.begin(), penalised_.end(), name)) continue;
    const auto at = std::lower_bound(touched.begin(), touched.end(), name);
    if (at == touched.end() || *at != name) touched.insert(at, name);
  }
}

const std::vector<std::string>& TouchCounter::end_step(sim::Session& session) const {
  sim::TaskState& state = session.task_state();
  state.touched_last_step = std::exchange(state.touched_this_step, {});
  return state.touched_last_step;
}

}  // namespace hrisim::tasks
