#include "sim/session.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <utility>

#include "core/error.hpp"
#include "core/state_hash.hpp"
#include "core/text.hpp"
#include "sim/choreography.hpp"
#include "sim/doors_and_elevators.hpp"
#include "sim/attractions.hpp"
#include "sim/queues.hpp"
#include "sim/robot_control.hpp"
#include "sim/search.hpp"
#include "sim/sensing.hpp"
#include "sim/sounds.hpp"

namespace hrisim::sim {
namespace {

using scenario::Action;
using scenario::AgentKind;
using Kind = scenario::Action::Kind;

/// Speed at which a choreographed robot follows its path, m/s (about the HSR's 0.8 km/h ceiling).
constexpr double kScriptedRobotSpeed = 0.22;

/// The state at tick 0: agents at their starts, groups, doors, elevators, scheduled requests, robots.
State initial_state(const scenario::Model& model, std::uint64_t seed) {
  State state;
  state.random = core::Random(seed);
  state.time_limit = model.time_limit;
  if (model.clock) {
    core::Random clock = state.random.stream("clock");
    state.clock_start = model.clock->latest_start > model.clock->start ? clock.uniform(model.clock->start, model.clock->latest_start) : model.clock->start;
  }
  core::Random speeds = state.random.stream("humans.preferred_speed");
  for (const scenario::AgentDef& def : model.agents) {
    AgentState agent;
    agent.position = def.start.position();
    agent.heading = def.start.theta;
    if (def.kind == AgentKind::human) {
      agent.preferred_speed = def.preferred_speed.value_or(std::clamp(speeds.normal(scenario::kPreferredSpeedMean, scenario::kPreferredSpeedStddev),
                                                                      scenario::kPreferredSpeedMin, scenario::kPreferredSpeedMax));
    } else if (def.robot_model && def.robot_model->drive) {
      agent.preferred_speed = def.robot_model->drive->params.max_linear_speed;
    } else {
      agent.preferred_speed = def.preferred_speed.value_or(kScriptedRobotSpeed);
    }
    agent.reaction.behaviour = def.behaviour;
    agent.active = def.enters_at <= 0.0;
    if (def.activity_model >= 0 || def.daily_schedule >= 0) agent.living.activity_random = state.random.stream("humans.activities." + def.id);
    state.agents.push_back(std::move(agent));
    if (def.robot_model) state.robots.emplace_back(static_cast<int>(state.agents.size() - 1), def, model.dt, state.random);
  }
  for (const scenario::Group& group : model.groups) state.groups.push_back(group.members);
  for (const scenario::Door& door : model.doors) state.doors.push_back(door.initially_open ? DoorState{DoorPhase::open, 1.0} : DoorState{});
  for (const scenario::Elevator& elevator : model.elevators) {
    ElevatorState cabin;
    cabin.floor = elevator.start_floor;
    state.elevators.push_back(cabin);
    for (int door : elevator.doors) {
      state.doors[door] = DoorState{};
      state.topics[elevator.topic + "/" + model.doors[door].name + "_state"] = "closed";
    }
  }
  state.attraction_random = state.random.stream("attractions");
  for (const scenario::Queue& queue : model.queues) state.queues.push_back({{}, -1, state.random.stream("queues." + queue.name)});
  state.steps.resize(model.steps.size());
  for (const scenario::Request& scripted : model.requests) state.scheduled.push_back({scripted.time, scripted.robot, scripted.routine});  // kept sorted
  return state;
}

/// Robot requests whose time has come are made.
void make_scheduled_requests(const scenario::Model& model, State& state) {
  while (!state.scheduled.empty() && state.scheduled.front().time <= time_of(model, state)) {
    const ScheduledRequest due = state.scheduled.front();
    state.scheduled.erase(state.scheduled.begin());
    make_request(model, state, due.robot, due.routine);
  }
}

}  // namespace

Action walk_action(int human, const Vec2& goal) {
  Action action;
  action.agent = human;
  action.kind = Kind::go_to_pose;
  action.pose = {goal.x(), goal.y(), 0.0};
  action.radius = scenario::kDefaultGoalRadius;
  action.pointer = "command: walk";
  return action;
}

Action motion_action(int human, const std::string& name, double seconds) {
  Action action;
  action.agent = human;
  action.kind = Kind::play_motion;
  action.motion = name;
  action.value = seconds;
  action.pointer = "command: motion " + name;
  return action;
}

Session::Session(std::shared_ptr<const scenario::Model> model, std::uint64_t seed)
    : model_(std::move(model)), state_(initial_state(*model_, seed)), bodies_(*model_), walking_(*model_) {
  for (std::size_t a = 0; a < model_->agents.size(); ++a) {
    ids_.add(static_cast<int>(a));
    runtime_of_agent_.push_back(-1);
  }
  for (std::size_t r = 0; r < state_.robots.size(); ++r) runtime_of_agent_[state_.robots[r].agent] = static_cast<int>(r);
  for (const RobotRuntime& runtime : state_.robots) {
    if (runtime.controller.goal) go_to(*model_, state_, runtime.agent, *runtime.controller.goal, runtime.controller.goal_radius, false);
  }
  physics_ = build_physics(*model_, state_, bodies_);
  if (!model_->steps.empty()) start_step(*model_, state_, 0);
}

Session::Session(std::shared_ptr<const scenario::Model> model, Copy copy, std::span<const Event> events)
    : model_(std::move(model)),
      ids_(std::move(copy.ids)),
      state_(std::move(copy.state)),
      runtime_of_agent_(std::move(copy.runtime_of_agent)),
      bodies_(*model_),
      walking_(*model_) {
  if (events.size() < copy.events) {
    throw core::Error(core::ErrorCode::internal, "a session copy of " + std::to_string(copy.events) + " events given only " +
                                                     std::to_string(events.size()) + ": not the session it was copied from");
  }
  state_.events.assign(events.begin(), events.begin() + static_cast<std::ptrdiff_t>(copy.events));
  physics_ = build_physics_again(*model_, state_, bodies_);
}

std::optional<Session::Copy> Session::copy() {
  if (physics_.world && physics_.built_at_tick != state_.tick) return std::nullopt;
  // The events are set aside while the rest is copied: they grow with the episode, and the session's
  // own are the copy's events, as they are only ever appended.
  std::vector<Event> events = std::exchange(state_.events, {});
  try {
    Copy copy{state_, ids_, runtime_of_agent_, events.size()};
    state_.events = std::move(events);
    return copy;
  } catch (...) {
    state_.events = std::move(events);
    throw;
  }
}

void Session::tick() {
  if (state_.finished) return;
  const scenario::Model& model = *model_;
  const std::size_t first_event = state_.events.size();
  let_people_in(model, state_);
  make_scheduled_requests(model, state_);
  update_doors_and_elevators(model, state_);
  update_requests(model, state_);
  update_choreography(model, state_);
  serve_queues(model, state_);
  draw_people_to_attractions(model, state_);
  if (state_.finished) return;
  decide_robots(model, state_);
  walk(model, state_, walking_);
  if (physics_.world) place_people_and_doors(model, state_, physics_, bodies_);
  move_robots(model, state_, physics_);
  make_sounds(model, state_, first_event);
  ++state_.tick;
  if (physics_.world) step_physics(model, state_, physics_, bodies_);  // the state after this tick: its events carry the new tick, as sensors do
  sense(model, state_, physics_, bodies_);
  listen(model, state_);
  notice_people_found(model, state_);
  end_at_time_limit();
  if (physics_.world) rebuild_physics_when_due(model, state_, physics_, bodies_);
}

void Session::end_at_time_limit() {
  if (time() < state_.time_limit) return;
  state_.finished = true;
  state_.termination = Termination::timeout;
  const bool in_step = state_.current_step < static_cast<int>(model_->steps.size());
  emit(*model_, state_, in_step ? model_->steps[state_.current_step].name : "", events::TimeLimit{state_.current_step});
}

void Session::end_by_task() {
  if (state_.finished) return;
  state_.finished = true;
  state_.termination = Termination::goal;
  emit(*model_, state_, model_->task ? model_->task->name : "", events::TaskEnded{});
}

AgentId Session::agent_id(const std::string& name) const {
  const int index = model_->find_agent(name);
  for (const AgentId id : ids_.ids()) {
    if (ids_.at(id) == index) return id;
  }
  throw core::Error(core::ErrorCode::not_found, "no agent '" + name + "' in this session", "agent", name);
}

AgentId Session::agent_at(int index) const {
  for (const AgentId id : ids_.ids()) {
    if (ids_.at(id) == index) return id;
  }
  const std::string name = index >= 0 && index < static_cast<int>(model_->agents.size()) ? model_->agents[index].id : std::to_string(index);
  throw core::Error(core::ErrorCode::not_found, "no agent '" + name + "' in this session", "agent", name);
}

void Session::remove_agent(AgentId id) {
  const int index = ids_.at(id);
  ids_.remove(id);
  leave_scene(*model_, state_, index, events::AgentRemoved{});
}

void Session::request(AgentId robot, int routine) { make_request(*model_, state_, index_of(robot), routine); }

void Session::schedule_request(double at, AgentId robot, int routine) {
  const ScheduledRequest request{at, index_of(robot), routine};
  const auto later = std::upper_bound(state_.scheduled.begin(), state_.scheduled.end(), request,
                                      [](const ScheduledRequest& a, const ScheduledRequest& b) { return a.time < b.time; });
  state_.scheduled.insert(later, request);
}


void Session::command_human(const Action& action, std::string text) {
  const int agent = action.agent;
  if (agent < 0 || agent >= static_cast<int>(model_->agents.size()) || model_->agents[agent].kind != AgentKind::human) {
    throw core::Error(core::ErrorCode::bad_request, "a command goes to a human");
  }
  interrupt(state_, agent, std::span<const Action>(&action, 1));
  emit(*model_, state_, model_->agents[agent].id, events::Command{std::move(text)});
}

void Session::command_robot(AgentId robot, const Vec2& velocity) {
  state_.agents[index_of(robot)].commanded_velocity = velocity;
}

void Session::command_robot_twist(AgentId robot, const robots::Twist& twist) {
  const int agent = index_of(robot);
  if (runtime_of_agent_[agent] < 0 || !model_->agents[agent].robot_model->drive) {
    throw core::Error(core::ErrorCode::conflict, "agent '" + model_->agents[agent].id + "' is not a robot with a drive");
  }
  // Velocity commands put the robot under external control, whatever its built-in controller was.
  RobotRuntime& runtime = state_.robots[runtime_of_agent_[agent]];
  runtime.controller.kind = scenario::RobotController::Kind::teleop;
  runtime.command = twist;
}

const RobotRuntime* Session::robot_runtime(AgentId agent) const {
  const int runtime = runtime_of_agent_[index_of(agent)];
  return runtime < 0 ? nullptr : &state_.robots[runtime];
}

void Session::command_robot_joints(AgentId robot, const std::string& group, const std::vector<double>& targets, bool velocities) {
  const int agent = index_of(robot);
  if (runtime_of_agent_[agent] < 0) throw core::Error(core::ErrorCode::conflict, "agent '" + model_->agents[agent].id + "' is not a robot with a model");
  state_.robots[runtime_of_agent_[agent]].robot.command_group(group, targets, velocities);
}

void Session::command_robot_gripper(AgentId robot, bool closed) {
  const int agent = index_of(robot);
  if (runtime_of_agent_[agent] < 0) throw core::Error(core::ErrorCode::conflict, "agent '" + model_->agents[agent].id + "' is not a robot with a model");
  state_.robots[runtime_of_agent_[agent]].robot.set_gripper(closed);
}

Eigen::Isometry3d Session::object_pose(int object) const {
  if (object < 0 || object >= static_cast<int>(state_.objects.size())) {
    throw core::Error(core::ErrorCode::not_found, "no object " + std::to_string(object));
  }
  return state_.objects[object].pose;
}

void Session::place_agent(AgentId id, const Pose2& pose) {
  const int agent = index_of(id);
  const Vec2 at = pose.position();
  if (!model_->grid.in_bounds(model_->grid.cell_of(at)) || model_->grid.blocked(at)) {
    throw core::Error(core::ErrorCode::bad_request, "(" + core::point_text(pose.position()) + ") is not free floor");
  }
  AgentState& state = state_.agents[agent];
  state.position = at;
  state.heading = core::wrap_angle(pose.theta);
  state.velocity = Vec2::Zero();
  state.attitude.target_heading.reset();
  if (state.navigation.under_way) {
    state.navigation.path.clear();  // planned again from here on the next step
    state.navigation.replan_at_tick = -1;
  } else {
    state.navigation.hold = at;
  }
  if (const int runtime = runtime_of_agent_[agent]; runtime >= 0) state_.robots[runtime].robot.set_pose({at.x(), at.y(), state.heading});
  emit(*model_, state_, model_->agents[agent].id, events::AgentPlaced{at.x(), at.y(), state.heading});
}

void Session::set_rooted(AgentId agent, bool rooted) { state_.agents[index_of(agent)].rooted = rooted; }

void Session::set_preferred_speed(AgentId human, double speed) {
  const int agent = index_of(human);
  if (model_->agents[agent].kind != AgentKind::human) {
    throw core::Error(core::ErrorCode::conflict, "agent '" + model_->agents[agent].id + "' is not a human");
  }
  state_.agents[agent].preferred_speed = speed;
}

void Session::place_object(int object, const Eigen::Isometry3d& pose) {
  object_pose(object);  // checks the index
  const int body = physics_.objects[object];
  if (physics_.world->holder(body) >= 0) {
    throw core::Error(core::ErrorCode::conflict, "object '" + model_->objects[object].name + "' is held by a gripper");
  }
  physics_.world->place(body, pose);
  state_.objects[object] = ObjectState{physics_.world->pose(body)};
  physics_.built_at_tick = -1;  // no longer the world a build from the state makes
  emit(*model_, state_, model_->objects[object].name, events::ObjectPlaced{pose.translation().x(), pose.translation().y(), pose.translation().z()});
}

humans::BodyCapsules Session::human_body(int agent) const { return bodies_.of(*model_, state_, agent); }

std::uint64_t Session::state_hash() const { return sim::state_hash(state_); }

std::string Session::state_hash_hex() const { return hash_hex(state_hash()); }

}  // namespace hrisim::sim
