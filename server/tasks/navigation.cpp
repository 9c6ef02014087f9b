// The navigation tasks: the default one of scenarios that name none, and the benchmark's
// approach_human, follow_human and approach_human_apartment (seed 003 §4.4.1–4.4.3).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "tasks/navigation.hpp"
#include "tasks/rewards.hpp"
#include "tasks/task_support.hpp"

namespace hrisim::tasks {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
/// Tries at drawing a free place before giving up.
constexpr int kPlacementTries = 10000;

}  // namespace

DefaultTask::DefaultTask(const sim::Session& session) {
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

  action_space_ = drive_ ? drive_action_space(robot) : box({-kDiscRobotMaxSpeed, -kDiscRobotMaxSpeed}, {kDiscRobotMaxSpeed, kDiscRobotMaxSpeed});
  std::vector<double> low, high;
  const double diagonal = add_robot_motion_bounds(model, action_space_.high[0], drive_ ? action_space_.high[1] : kInfinity, low, high);
  low.insert(low.end(), {-diagonal, -diagonal});
  high.insert(high.end(), {diagonal, diagonal});
  for (int p = 0; p < kObservedPeople; ++p) {
    low.insert(low.end(), {0, -kObservationRange, -kObservationRange, -kInfinity, -kInfinity});
    high.insert(high.end(), {1, kObservationRange, kObservationRange, kInfinity, kInfinity});
  }
  observation_space_ = box(std::move(low), std::move(high));
}

std::vector<double> DefaultTask::observe(const sim::Session& session) const {
  const scenario::Model& model = session.model();
  const sim::AgentState& robot = session.state().agents[robot_];
  std::vector<double> observation = robot_motion(session, robot_);
  const scenario::RobotController& controller = model.agents[robot_].controller;
  const core::Vec2 goal = controller.goal ? core::in_frame(robot.heading, controller.goal->position() - robot.position) : core::Vec2::Zero();
  observation.insert(observation.end(), {goal.x(), goal.y()});
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
    const core::Vec2 at = core::in_frame(robot.heading, person.position - robot.position), moving = core::in_frame(robot.heading, person.velocity);
    observation.insert(observation.end(), {1.0, at.x(), at.y(), moving.x(), moving.y()});
  }
  return observation;
}

int DefaultTask::act(sim::Session& session, const std::vector<double>& action) const {
  if (drive_) {
    drive(session, robot_, action, action_space_);
  } else {
    const double a = std::clamp(action[0], action_space_.low[0], action_space_.high[0]);
    const double b = std::clamp(action[1], action_space_.low[1], action_space_.high[1]);
    session.command_robot(session.agent_at(robot_), {a, b});
  }
  return 1;
}

NavigationTask::NavigationTask(const sim::Session& session) : task_(*session.model().task), touches_(task_) {
  const scenario::Model& model = session.model();
  action_space_ = drive_action_space(model.agents[task_.robot]);
  std::vector<double> low, high;
  const double diagonal = add_robot_motion_bounds(model, action_space_.high[0], action_space_.high[1], low, high);
  low.insert(low.end(), {-diagonal, -diagonal, -kInfinity, -kInfinity, 0});
  high.insert(high.end(), {diagonal, diagonal, kInfinity, kInfinity, diagonal});
  observation_space_ = box(std::move(low), std::move(high));
}

core::Vec2 NavigationTask::free_place(const sim::Session& session, core::Random& random, const core::Vec2& away_from, double clearance) const {
  const scenario::Model& model = session.model();
  const double radius = model.agents[task_.human].radius;
  for (int attempt = 0; attempt < kPlacementTries; ++attempt) {
    const core::Vec2 at(random.uniform(task_.spawn_min.x(), task_.spawn_max.x()), random.uniform(task_.spawn_min.y(), task_.spawn_max.y()));
    if (!model.grid.in_bounds(model.grid.cell_of(at)) || model.grid.blocked(at)) continue;
    if (model.field.distance(model.grid, at) < radius) continue;
    if ((at - away_from).norm() < clearance) continue;
    return at;
  }
  throw core::Error(core::ErrorCode::conflict, "task " + task_.name + ": found no free place for the human in the spawn area");
}

void NavigationTask::begin(sim::Session& session) const {
  const scenario::Model& model = session.model();
  const sim::AgentState& robot = session.state().agents[task_.robot];
  const sim::AgentId human = session.agent_at(task_.human);
  // The session's calls below leave the task's state alone: `state` stays valid.
  sim::NavigationTaskState& state = session.task_state().kind_state.emplace<sim::NavigationTaskState>();
  state.random = session.state().random.stream("task");
  // The human's disc clear of the robot's footprint.
  const double clearance = model.agents[task_.human].radius + model.agents[task_.robot].robot_model->footprint_radius;
  if (task_.kind == scenario::TaskKind::follow_human) {
    const core::Vec2 ahead = robot.position + core::heading_vector(robot.heading) * std::max(task_.lead_distance, clearance);
    session.place_agent(human, {ahead.x(), ahead.y(), robot.heading});
    const scenario::WalkingStyle& style = task_.walking_styles[static_cast<std::size_t>(state.random.uniform() * task_.walking_styles.size()) %
                                                               task_.walking_styles.size()];
    state.walking_style = style.name;
    session.set_preferred_speed(human, style.speed);
    walk_on(session, state.random);
  } else {
    const core::Vec2 at = free_place(session, state.random, robot.position, clearance);
    session.place_agent(human, {at.x(), at.y(), state.random.uniform(-std::numbers::pi, std::numbers::pi)});
    session.set_rooted(human, true);  // she stands idle (an animation), not stepping aside
  }
  state.gap = distance(session);
}

void NavigationTask::walk_on(sim::Session& session, core::Random& random) const {
  const sim::AgentState& person = session.state().agents[task_.human];
  const core::Vec2 goal = free_place(session, random, person.position, kFollowMinLeg);
  session.command_human(sim::walk_action(task_.human, goal), "walk " + core::point_text(goal));
}

double NavigationTask::distance(const sim::Session& session) const {
  // Between the bodies: the seed's human has no collider, so its root-to-base distance could reach
  // 0.3 m; hrisim's people are solid, and the footprints' gap is what the robot can close.
  const scenario::Model& model = session.model();
  const double centres = (session.state().agents[task_.human].position - session.state().agents[task_.robot].position).norm();
  return centres - model.agents[task_.human].radius - model.agents[task_.robot].radius;
}

std::vector<double> NavigationTask::observe(const sim::Session& session) const {
  const sim::AgentState& robot = session.state().agents[task_.robot];
  const sim::AgentState& human = session.state().agents[task_.human];
  const core::Vec2 at = core::in_frame(robot.heading, human.position - robot.position), moving = core::in_frame(robot.heading, human.velocity);
  std::vector<double> observation = robot_motion(session, task_.robot);
  observation.insert(observation.end(), {at.x(), at.y(), moving.x(), moving.y(), distance(session)});
  return observation;
}

int NavigationTask::act(sim::Session& session, const std::vector<double>& action) const {
  drive(session, task_.robot, action, action_space_);
  return task_.frame_skip;
}

void NavigationTask::after_tick(sim::Session& session) const { touches_.after_tick(session); }

Reward NavigationTask::reward(sim::Session& session) const {
  sim::NavigationTaskState& state = std::get<sim::NavigationTaskState>(session.task_state().kind_state);
  const double previous = state.gap;
  state.gap = distance(session);
  const std::vector<std::string>& touched = touches_.end_step(session);
  return sum_of({{"distance", distance_reward(previous, state.gap)},
                 {"collision_human", human_collision_reward(state.gap, task_.collision_distance, task_.collision_penalty)},
                 {"collision_obstacle", obstacle_collision_reward(static_cast<int>(touched.size()), task_.obstacle_penalty)}});
}

nlohmann::json NavigationTask::info(const sim::Session& session) const {
  const sim::TaskState& task = session.state().task;
  if (task.last_reward_terms.empty()) return nlohmann::json::object();  // no step ended yet
  const sim::NavigationTaskState& state = std::get<sim::NavigationTaskState>(task.kind_state);
  nlohmann::json info = {{"distance", state.gap},
                         {"distance_reward", term(task.last_reward_terms, "distance")},
                         {"collision_human", term(task.last_reward_terms, "collision_human")},
                         {"collision_obstacle", term(task.last_reward_terms, "collision_obstacle")},
                         {"touched", task.touched_last_step}};
  if (task_.kind == scenario::TaskKind::follow_human) info["walking_style"] = state.walking_style;
  return info;
}

void NavigationTask::before_step(sim::Session& session) const {
  if (task_.kind == scenario::TaskKind::follow_human && session.state().agents[task_.human].program.empty()) {
    walk_on(session, std::get<sim::NavigationTaskState>(session.task_state().kind_state).random);
  }
}

bool NavigationTask::terminated(const sim::Session& session) const {
  return scenario::has_goal_condition(task_.kind) && distance(session) < task_.reach_distance;
}

}  // namespace hrisim::tasks
