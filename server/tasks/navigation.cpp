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

int DefaultTask::act(sim::Session& session, const std::vector<double>& action) {
  if (drive_) {
    drive(session, robot_, action, action_space_);
  } else {
    const double a = std::clamp(action[0], action_space_.low[0], action_space_.high[0]);
    const double b = std::clamp(action[1], action_space_.low[1], action_space_.high[1]);
    session.command_robot(session.agent_at(robot_), {a, b});
  }
  return 1;
}

NavigationTask::NavigationTask(const sim::Session& session)
    : task_(*session.model().task), touches_(task_), random_(session.state().random.stream("task")) {
  const scenario::Model& model = session.model();
  action_space_ = drive_action_space(model.agents[task_.robot]);
  std::vector<double> low, high;
  const double diagonal = add_robot_motion_bounds(model, action_space_.high[0], action_space_.high[1], low, high);
  low.insert(low.end(), {-diagonal, -diagonal, -kInfinity, -kInfinity, 0});
  high.insert(high.end(), {diagonal, diagonal, kInfinity, kInfinity, diagonal});
  observation_space_ = box(std::move(low), std::move(high));
}

core::Vec2 NavigationTask::free_place(const sim::Session& session, const core::Vec2& away_from, double clearance) {
  const scenario::Model& model = session.model();
  const double radius = model.agents[task_.human].radius;
  for (int attempt = 0; attempt < kPlacementTries; ++attempt) {
    const core::Vec2 at(random_.uniform(task_.spawn_min.x(), task_.spawn_max.x()), random_.uniform(task_.spawn_min.y(), task_.spawn_max.y()));
    if (!model.grid.in_bounds(model.grid.cell_of(at)) || model.grid.blocked(at)) continue;
    if (model.field.distance(model.grid, at) < radius) continue;
    if ((at - away_from).norm() < clearance) continue;
    return at;
  }
  throw core::Error(core::ErrorCode::conflict, "task " + task_.name + ": found no free place for the human in the spawn area");
}

void NavigationTask::begin(sim::Session& session) {
  const scenario::Model& model = session.model();
  const sim::AgentState& robot = session.state().agents[task_.robot];
  const sim::AgentId human = session.agent_at(task_.human);
  // The human's disc clear of the robot's footprint.
  const double clearance = model.agents[task_.human].radius + model.agents[task_.robot].robot_model->footprint_radius;
  if (task_.kind == scenario::TaskKind::follow_human) {
    const core::Vec2 ahead = robot.position + core::heading_vector(robot.heading) * std::max(task_.lead_distance, clearance);
    session.place_agent(human, {ahead.x(), ahead.y(), robot.heading});
    const scenario::WalkingStyle& style = task_.walking_styles[static_cast<std::size_t>(random_.uniform() * task_.walking_styles.size()) %
                                                               task_.walking_styles.size()];
    style_ = style.name;
    session.set_preferred_speed(human, style.speed);
    walk_on(session);
  } else {
    const core::Vec2 at = free_place(session, robot.position, clearance);
    session.place_agent(human, {at.x(), at.y(), random_.uniform(-std::numbers::pi, std::numbers::pi)});
    session.set_rooted(human, true);  // she stands idle (an animation), not stepping aside
  }
  distance_ = distance(session);
}

void NavigationTask::walk_on(sim::Session& session) {
  const sim::AgentState& person = session.state().agents[task_.human];
  const core::Vec2 goal = free_place(session, person.position, kFollowMinLeg);
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

int NavigationTask::act(sim::Session& session, const std::vector<double>& action) {
  drive(session, task_.robot, action, action_space_);
  return task_.frame_skip;
}

void NavigationTask::after_tick(const sim::Session& session) { touches_.after_tick(session); }

Reward NavigationTask::reward(const sim::Session& session) {
  const double previous = distance_;
  distance_ = distance(session);
  touched_ = touches_.take();
  const Reward reward = sum_of({{"distance", distance_reward(previous, distance_)},
                                {"collision_human", human_collision_reward(distance_, task_.collision_distance, task_.collision_penalty)},
                                {"collision_obstacle", obstacle_collision_reward(static_cast<int>(touched_.size()), task_.obstacle_penalty)}});
  terms_ = {{"distance", distance_},
            {"distance_reward", reward.terms[0].second},
            {"collision_human", reward.terms[1].second},
            {"collision_obstacle", reward.terms[2].second},
            {"touched", touched_}};
  if (task_.kind == scenario::TaskKind::follow_human) terms_["walking_style"] = style_;
  return reward;
}

void NavigationTask::before_step(sim::Session& session) {
  if (task_.kind == scenario::TaskKind::follow_human && session.state().agents[task_.human].program.empty()) walk_on(session);
}

bool NavigationTask::terminated(const sim::Session& session) const {
  return scenario::has_goal_condition(task_.kind) && distance(session) < task_.reach_distance;
}

}  // namespace hrisim::tasks
