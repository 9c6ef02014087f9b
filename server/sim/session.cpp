#include "sim/session.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

#include "core/error.hpp"
#include "core/portable_math.hpp"
#include "core/state_hash.hpp"
#include "core/text.hpp"

namespace hrisim::sim {
namespace {

using scenario::Action;
using scenario::AgentKind;
using Kind = scenario::Action::Kind;

/// Speed at which a choreographed robot follows its path, m/s (about the HSR's 0.8 km/h ceiling).
constexpr double kScriptedRobotSpeed = 0.22;
/// Instant actions (publish, zero waits) chained within one tick per agent, at most.
constexpr int kMaxActionsPerTick = 64;

double direction_to(const Vec2& from, const Vec2& to) { return std::atan2(to.y() - from.y(), to.x() - from.x()); }

}  // namespace

Session::Session(std::shared_ptr<const scenario::Model> model, std::uint64_t seed)
    : model_(std::move(model)), time_limit_(model_->time_limit), crowd_(model_->orca, model_->social_force) {
  state_.random = core::Random(seed);
  core::Random speeds = state_.random.stream("humans.preferred_speed");
  for (const scenario::AgentDef& def : model_->agents) {
    AgentState agent;
    agent.position = def.start.position();
    agent.heading = def.start.theta;
    if (def.kind == AgentKind::human) {
      agent.preferred_speed = def.preferred_speed.value_or(
          std::clamp(speeds.normal(scenario::kPreferredSpeedMean, scenario::kPreferredSpeedStddev),
                     scenario::kPreferredSpeedMin, scenario::kPreferredSpeedMax));
    } else if (def.robot_model && def.robot_model->drive) {
      agent.preferred_speed = def.robot_model->drive->params.max_linear_speed;
    } else {
      agent.preferred_speed = def.preferred_speed.value_or(kScriptedRobotSpeed);
    }
    state_.agents.push_back(std::move(agent));
    body_cache_.emplace_back();
    skeletons_.push_back(def.kind == AgentKind::human ? std::optional(humans::Skeleton(humans::body_dimensions(def.type).value_or(humans::kAdultBody)))
                                                      : std::nullopt);
    ids_.add(static_cast<int>(state_.agents.size() - 1));
    runtime_of_agent_.push_back(def.robot_model ? static_cast<int>(robots_.size()) : -1);
    if (def.robot_model) robots_.emplace_back(static_cast<int>(state_.agents.size() - 1), def, model_->dt, state_.random);
  }
  for (const scenario::Group& group : model_->groups) state_.groups.push_back(group.members);
  for (const scenario::Door& door : model_->doors) {
    state_.doors.push_back(door.initially_open ? DoorState{DoorPhase::open, 1.0} : DoorState{});
  }
  for (const scenario::Elevator& elevator : model_->elevators) {
    ElevatorState cabin;
    cabin.floor = elevator.start_floor;
    state_.elevators.push_back(cabin);
    for (int door : elevator.doors) {
      state_.doors[door] = DoorState{};
      state_.topics[elevator.topic + "/" + model_->doors[door].name + "_state"] = "closed";
    }
  }
  state_.steps.resize(model_->steps.size());
  for (const scenario::Request& scripted : model_->requests) {
    state_.scheduled.push_back({scripted.time, scripted.robot, scripted.task});  // the model keeps them sorted
  }
  for (const RobotRuntime& runtime : robots_) {
    if (runtime.controller.goal) go_to(runtime.agent, *runtime.controller.goal, runtime.controller.goal_radius, false);
  }
  if (!robots_.empty() || !model_->objects.empty()) build_physics();
  if (!model_->steps.empty()) start_step(0);
}

AgentId Session::agent_id(const std::string& name) const {
  const int index = model_->find_agent(name);
  for (const AgentId id : ids_.ids()) {
    if (ids_.at(id) == index) return id;
  }
  throw core::Error(core::ErrorCode::not_found, "no agent '" + name + "' in this session", {{"agent", name}});
}

void Session::remove_agent(AgentId id) {
  const int index = ids_.at(id);
  ids_.remove(id);
  AgentState& agent = state_.agents[index];
  agent.active = false;
  agent.program.clear();
  agent.navigating = false;
  agent.velocity = Vec2::Zero();
  release_reservations(index);
  for (auto& members : state_.groups) std::erase(members, index);
  emit("agent_removed", model_->agents[index].id);
}

void Session::schedule_request(double at, AgentId robot, int task) {
  const ScheduledRequest request{at, index_of(robot), task};
  const auto later = std::upper_bound(state_.scheduled.begin(), state_.scheduled.end(), request,
                                      [](const ScheduledRequest& a, const ScheduledRequest& b) { return a.time < b.time; });
  state_.scheduled.insert(later, request);
}

std::int64_t Session::ticks(double seconds) const {
  return static_cast<std::int64_t>(std::llround(seconds / model_->dt));
}

void Session::emit(std::string kind, std::string subject, nlohmann::json data) {
  state_.events.push_back({state_.tick, time(), std::move(kind), std::move(subject), std::move(data)});
}

const Action& Session::action_of(const PendingAction& pending) const {
  if (pending.task == kCommandedAction) return state_.commanded[pending.index];
  return pending.task >= 0 ? model_->tasks[pending.task].actions[pending.index]
                           : model_->steps[pending.step].actions[pending.index];
}

scenario::Action Session::parse_human_command(AgentId human, std::string_view text) const {
  const int agent = index_of(human);
  if (model_->agents[agent].kind != AgentKind::human) {
    throw core::Error(core::ErrorCode::bad_request, "'" + model_->agents[agent].id + "' is not a human");
  }
  std::istringstream in{std::string(text)};
  std::string verb;
  in >> verb;
  auto number = [&](const char* what) {
    double value = 0.0;
    if (!(in >> value) || !std::isfinite(value)) {
      throw core::Error(core::ErrorCode::bad_request, verb + ": " + what + " must be a number (" + std::string(text) + ")");
    }
    return value;
  };
  Action action;
  action.agent = agent;
  action.pointer = "command: " + std::string(text);
  if (verb == "walk") {
    action.kind = Kind::go_to_pose;
    const double x = number("x"), y = number("y");
    action.pose = {x, y, 0.0};
    action.radius = scenario::kDefaultGoalRadius;
    const Vec2 goal(x, y);
    if (!model_->grid.in_bounds(model_->grid.cell_of(goal)) || model_->grid.blocked(goal)) {
      throw core::Error(core::ErrorCode::bad_request, "walk: (" + core::point_text(goal) + ") is not free floor");
    }
  } else if (verb == "wait") {
    action.kind = Kind::wait_duration;
    action.value = number("seconds");
    if (action.value < 0.0) throw core::Error(core::ErrorCode::bad_request, "wait: seconds must not be negative");
  } else if (verb == "turn_to") {
    action.kind = Kind::turn_to;
    action.value = number("heading");
  } else if (verb == "look_at") {
    std::string name;
    if (!(in >> name)) throw core::Error(core::ErrorCode::bad_request, "look_at: whom or what? (an agent or a location)");
    if (const int other = model_->find_agent(name); other >= 0) {
      action.kind = Kind::look_at_agent;
      action.target = other;
    } else {
      const auto location = std::find_if(model_->locations.begin(), model_->locations.end(),
                                         [&](const scenario::Location& l) { return l.name == name; });
      if (location == model_->locations.end()) {
        throw core::Error(core::ErrorCode::bad_request, "look_at: no agent or location named '" + name + "'");
      }
      action.kind = Kind::look_at_location;
      action.target = static_cast<int>(location - model_->locations.begin());
    }
  } else if (verb == "motion") {
    if (!(in >> action.motion) || !humans::builtin_motion(action.motion)) {
      throw core::Error(core::ErrorCode::bad_request, "motion: which primitive? (" + core::join(humans::builtin_motion_names()) + ")");
    }
    action.kind = Kind::play_motion;
    action.value = humans::builtin_motion(action.motion)->duration();
    if (in >> std::ws; !in.eof()) {
      action.value = number("seconds");
      if (action.value <= 0.0) throw core::Error(core::ErrorCode::bad_request, "motion: seconds must be > 0");
    }
  } else {
    throw core::Error(core::ErrorCode::bad_request,
                      "unknown command '" + verb + "' (walk X Y, wait S, turn_to RAD, look_at NAME, motion NAME [S])");
  }
  std::string extra;
  if (in >> extra) throw core::Error(core::ErrorCode::bad_request, verb + ": unexpected '" + extra + "'");
  return action;
}

void Session::command_human(AgentId human, std::string_view text) {
  const Action action = parse_human_command(human, text);
  const int agent = action.agent;
  AgentState& state = state_.agents[agent];
  // The command goes first; what the human was doing starts again afterwards.
  state_.commanded.push_back(action);
  state.program.push_front({kCommandedAction, static_cast<int>(state_.commanded.size()) - 1, -1});
  state.action_started = false;
  state.navigating = false;
  state.path.clear();
  emit("command", model_->agents[agent].id, {{"text", std::string(text)}});
}

void Session::start_step(int step) {
  state_.step = step;
  state_.steps[step].started_tick = state_.tick;
  const scenario::Step& definition = model_->steps[step];
  emit("step_started", definition.name, {{"index", step}});
  for (std::size_t i = 0; i < definition.actions.size(); ++i) {
    const Action& action = definition.actions[i];
    if (action.group < 0) {
      state_.agents[action.agent].program.push_back({-1, static_cast<int>(i), step});
      continue;
    }
    const std::vector<int>& members = state_.groups[action.group];
    if (members.empty()) emit("group_empty", model_->groups[action.group].name, {{"step", definition.name}});
    for (std::size_t role = 0; role < members.size(); ++role) {
      state_.agents[members[role]].program.push_back(
          {-1, static_cast<int>(i), step, static_cast<int>(role), static_cast<int>(members.size())});
    }
  }
}

void Session::step() {
  if (state_.finished) return;
  while (!state_.scheduled.empty() && state_.scheduled.front().time <= time()) {
    const ScheduledRequest due = state_.scheduled.front();
    state_.scheduled.erase(state_.scheduled.begin());
    make_request(due.robot, due.task);
  }
  update_environment();
  update_requests();
  update_choreography();
  if (state_.finished) return;
  decide_robots();
  locomotion();
  move_robots();
  ++state_.tick;
  if (physics_) step_physics();  // the state after this step: its events carry the new tick, as sensors do
  sense();
  if (time() >= time_limit_) {
    state_.finished = true;
    state_.termination = "timeout";
    const bool in_step = state_.step < static_cast<int>(model_->steps.size());
    emit("time_limit", in_step ? model_->steps[state_.step].name : "", {{"step", state_.step}});
  }
}

void Session::end_by_task() {
  if (state_.finished) return;
  state_.finished = true;
  state_.termination = "goal";
  emit("task_ended", model_->task ? model_->task->name : "");
}

void Session::request(AgentId robot, int task) { make_request(index_of(robot), task); }

void Session::make_request(int robot, int task) {
  const Vec2 position = state_.agents[robot].position;
  const std::int64_t id = state_.next_request_id++;
  emit("request", model_->agents[robot].id,
       {{"request", id}, {"task", model_->tasks[task].name}, {"x", position.x()}, {"y", position.y()}});
  if (std::find(model_->async_tasks.begin(), model_->async_tasks.end(), task) == model_->async_tasks.end()) {
    emit("request_dropped", model_->agents[robot].id,
         {{"request", id}, {"task", model_->tasks[task].name}, {"reason", "the scenario has no response for this task"}});
    return;
  }
  state_.requests.push_back({id, robot, task, position, state_.tick, state_.tick});
}

namespace {

const char* phase_name(DoorPhase phase) {
  switch (phase) {
    case DoorPhase::closed: return "closed";
    case DoorPhase::opening: return "opening";
    case DoorPhase::open: return "open";
    case DoorPhase::closing: return "closing";
  }
  return "closed";
}

}  // namespace

void Session::update_environment() {
  // Requests published since the last tick reach the elevators in the order they were made.
  for (const Message& message : state_.inbox) {
    for (std::size_t e = 0; e < model_->elevators.size(); ++e) {
      const scenario::Elevator& elevator = model_->elevators[e];
      if (message.topic != elevator.request_topic()) continue;
      int floor = -1;
      for (std::size_t d = 0; d < elevator.doors.size(); ++d) {
        if (message.text == model_->doors[elevator.doors[d]].name || message.text == "floor" + std::to_string(d + 1)) {
          floor = static_cast<int>(d);
        }
      }
      if (floor < 0) {
        emit("elevator_ignored_request", elevator.name, {{"message", message.text}});
        continue;
      }
      std::deque<int>& queue = state_.elevators[e].queue;
      if (queue.empty() || queue.back() != floor) queue.push_back(floor);
    }
  }
  state_.inbox.clear();
  for (std::size_t e = 0; e < model_->elevators.size(); ++e) update_elevator(static_cast<int>(e));
}

void Session::set_door(int door, DoorPhase phase) {
  if (state_.doors[door].phase == phase) return;
  state_.doors[door].phase = phase;
  for (const scenario::Elevator& elevator : model_->elevators) {
    if (std::find(elevator.doors.begin(), elevator.doors.end(), door) == elevator.doors.end()) continue;
    state_.topics[elevator.topic + "/" + model_->doors[door].name + "_state"] = phase_name(phase);
  }
  emit("door_state", model_->doors[door].name, {{"state", phase_name(phase)}});
}

void Session::update_elevator(int index) {
  const scenario::Elevator& elevator = model_->elevators[index];
  ElevatorState& cabin = state_.elevators[index];
  const int door = elevator.doors[cabin.floor];
  DoorState& door_state = state_.doors[door];
  const double step = elevator.door_speed * model_->dt / std::max(model_->doors[door].width(), 1e-6);
  using Phase = ElevatorState::Phase;
  switch (cabin.phase) {
    case Phase::idle:
      if (cabin.queue.empty()) break;
      if (cabin.queue.front() == cabin.floor) {
        cabin.queue.pop_front();
        cabin.phase = Phase::opening;
        set_door(door, DoorPhase::opening);
      } else {
        cabin.destination = cabin.queue.front();
        cabin.phase = Phase::travelling;
        cabin.until_tick = state_.tick + ticks((elevator.travel_time + elevator.settle_time));
        emit("elevator_departed", elevator.name, {{"from", cabin.floor + 1}, {"to", cabin.destination + 1}});
      }
      break;
    case Phase::travelling:
      if (state_.tick >= cabin.until_tick) {
        cabin.floor = cabin.destination;
        cabin.phase = Phase::idle;
        emit("elevator_arrived", elevator.name, {{"floor", cabin.floor + 1}});
      }
      break;
    case Phase::opening:
      door_state.opening = std::min(1.0, door_state.opening + step);
      if (door_state.opening >= 1.0) {
        cabin.phase = Phase::open;
        cabin.until_tick = std::max(cabin.reopened_until_tick,
                                    state_.tick + ticks(elevator.open_time));
        set_door(door, DoorPhase::open);
      }
      break;
    case Phase::open:
      // Asked again for this floor: stay open longer; asked for another floor: close and go.
      while (!cabin.queue.empty() && cabin.queue.front() == cabin.floor) {
        cabin.queue.pop_front();
        cabin.until_tick = state_.tick + ticks(elevator.open_time);
      }
      if (state_.tick >= cabin.until_tick || (!cabin.queue.empty() && state_.tick >= cabin.reopened_until_tick)) {
        cabin.phase = Phase::closing;
        set_door(door, DoorPhase::closing);
      }
      break;
    case Phase::closing:
      if (someone_in_doorway(door)) {
        cabin.phase = Phase::opening;
        cabin.reopened_until_tick =
            state_.tick + ticks(scenario::kElevatorReopenHold);
        set_door(door, DoorPhase::opening);
        break;
      }
      door_state.opening = std::max(0.0, door_state.opening - step);
      if (door_state.opening <= 0.0) {
        cabin.phase = Phase::idle;
        set_door(door, DoorPhase::closed);
        for (AgentState& agent : state_.agents) {
          if (std::find(elevator.social_spaces.begin(), elevator.social_spaces.end(), agent.reserved_space) !=
              elevator.social_spaces.end()) {
            agent.reserved_space = -1;
            agent.reserved_slot = -1;
          }
        }
      }
      break;
  }
}

bool Session::door_blocks(int door) const { return state_.doors[door].phase != DoorPhase::open; }

bool Session::someone_in_doorway(int door) const {
  const scenario::Door& geometry = model_->doors[door];
  for (std::size_t a = 0; a < state_.agents.size(); ++a) {
    if (!state_.agents[a].active) continue;
    const Vec2& p = state_.agents[a].position;
    const double clearance = model_->agents[a].radius + geometry.thickness / 2;
    if ((core::closest_point_on_segment(p, geometry.from, geometry.to) - p).norm() < clearance) return true;
  }
  return false;
}

std::vector<std::size_t> Session::blocked_door_cells(double radius) const {
  std::vector<std::size_t> cells;
  const world::OccupancyGrid& grid = model_->grid;
  for (std::size_t d = 0; d < model_->doors.size(); ++d) {
    if (!door_blocks(static_cast<int>(d))) continue;
    const scenario::Door& door = model_->doors[d];
    // Cells whose centre a disc of `radius` could not occupy without touching the closed door.
    const double reach = radius + door.thickness / 2 + grid.resolution() / 2;
    const world::CellIndex low = grid.cell_of(door.from.cwiseMin(door.to) - Vec2(reach, reach));
    const world::CellIndex high = grid.cell_of(door.from.cwiseMax(door.to) + Vec2(reach, reach));
    for (int y = std::max(low.y, 0); y <= std::min(high.y, grid.height() - 1); ++y) {
      for (int x = std::max(low.x, 0); x <= std::min(high.x, grid.width() - 1); ++x) {
        const Vec2 centre = grid.center_of({x, y});
        if ((core::closest_point_on_segment(centre, door.from, door.to) - centre).norm() < reach) {
          cells.push_back(grid.index({x, y}));
        }
      }
    }
  }
  return cells;
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
  RobotRuntime& runtime = robots_[runtime_of_agent_[agent]];
  runtime.controller.kind = scenario::RobotController::Kind::teleop;
  runtime.command = twist;
}

const RobotRuntime* Session::robot_runtime(AgentId agent) const {
  const int runtime = runtime_of_agent_[index_of(agent)];
  return runtime < 0 ? nullptr : &robots_[runtime];
}

bool Session::idle(int agent) const {
  return state_.agents[agent].active && model_->agents[agent].kind == AgentKind::human && state_.agents[agent].program.empty() &&
         !state_.agents[agent].answering_request;
}

void Session::update_requests() {
  const auto retry = ticks(kRequestRetryPeriod);
  const auto timeout = ticks(kRequestTimeout);
  std::vector<OpenRequest> still_open;
  for (OpenRequest& open : state_.requests) {
    if (state_.tick < open.next_try_tick) {
      still_open.push_back(open);
      continue;
    }
    int chosen = -1;
    double chosen_distance = kRequestRadius;
    for (std::size_t h = 0; h < state_.agents.size(); ++h) {
      const double distance = (state_.agents[h].position - open.position).norm();
      if (idle(static_cast<int>(h)) && distance <= chosen_distance && (chosen < 0 || distance < chosen_distance)) {
        chosen = static_cast<int>(h);
        chosen_distance = distance;
      }
    }
    const std::string& task_name = model_->tasks[open.task].name;
    if (chosen >= 0) {
      AgentState& human = state_.agents[chosen];
      human.answering_request = true;
      for (std::size_t i = 0; i < model_->tasks[open.task].actions.size(); ++i) {
        human.program.push_back({open.task, static_cast<int>(i), -1});
      }
      emit("request_accepted", model_->agents[chosen].id,
           {{"request", open.id}, {"task", task_name}, {"robot", model_->agents[open.robot].id}, {"distance", chosen_distance}});
    } else if (state_.tick - open.asked_tick + retry > timeout) {
      emit("request_dropped", model_->agents[open.robot].id,
           {{"request", open.id}, {"task", task_name}, {"reason", "no idle human within 3 m"}});
    } else {
      open.next_try_tick += retry;
      still_open.push_back(open);
    }
  }
  state_.requests = std::move(still_open);
}

void Session::update_choreography() {
  // A finished step hands over to the next within the same tick, so its actions start without delay.
  for (std::size_t guard = 0; guard <= model_->steps.size(); ++guard) {
    for (std::size_t a = 0; a < state_.agents.size(); ++a) advance_agent(static_cast<int>(a));
    const int step = state_.step;
    if (step >= static_cast<int>(model_->steps.size())) {
      if (!state_.finished && !model_->task) {  // a task's episode ends by the task or its length
        state_.finished = true;
        state_.termination = "scenario_end";
        emit("scenario_finished", model_->name);
      }
      return;
    }
    for (const AgentState& agent : state_.agents) {
      for (const PendingAction& pending : agent.program) {
        if (pending.step == step) return;
      }
    }
    state_.steps[step].finished_tick = state_.tick;
    emit("step_finished", model_->steps[step].name,
         {{"index", step},
          {"duration", static_cast<double>(state_.tick - state_.steps[step].started_tick) * model_->dt}});
    if (step + 1 < static_cast<int>(model_->steps.size())) {
      start_step(step + 1);
    } else {
      state_.step = step + 1;
    }
  }
}

bool Session::advance_agent(int agent) {
  AgentState& state = state_.agents[agent];
  for (int guard = 0; guard < kMaxActionsPerTick && !state.program.empty(); ++guard) {
    const PendingAction pending = state.program.front();
    const Action& action = action_of(pending);
    if (action.kind == Kind::run_task) {
      state.program.pop_front();
      const auto& actions = model_->tasks[action.target].actions;
      for (std::size_t i = actions.size(); i-- > 0;) {
        state.program.push_front({action.target, static_cast<int>(i), pending.step});
      }
      continue;
    }
    if (!state.action_started) {
      if (!start_action(agent, action, pending)) return false;
      state.action_started = true;
    }
    if (!action_done(agent, action)) return false;
    finish_action(agent);
  }
  return true;
}

namespace {

/// Spot of member `role` of a group of `size` in the leader's frame: a pair side by side, larger
/// groups three abreast in rows behind the leader.
Vec2 formation_offset(int role, int size) {
  if (size == 2) return {0.0, -scenario::kFormationSpacing};
  static constexpr double kLateral[] = {0.0, -1.0, 1.0};
  return {-scenario::kFormationRowGap * (role / 3), kLateral[role % 3] * scenario::kFormationSpacing};
}

}  // namespace

bool Session::start_action(int agent, const Action& action, const PendingAction& pending) {
  AgentState& state = state_.agents[agent];
  // A follower in a group goto to a place walks in formation beside or behind the leader.
  if (action.group >= 0 && pending.role > 0 && action.kind != Kind::go_to_social_space) {
    release_reservations(agent);
    state.hold.reset();
    state.follow_leader = state_.groups[action.group].front();
    state.formation_offset = formation_offset(pending.role, pending.group_size);
    return true;
  }
  switch (action.kind) {
    case Kind::go_to_location: {
      // The location itself holds one person; a spot at an offset from it is not the location.
      const bool at_location = action.pose == Pose2{};
      for (std::size_t other = 0; other < state_.agents.size() && at_location; ++other) {
        if (static_cast<int>(other) != agent && state_.agents[other].reserved_location == action.target) return false;
      }
      release_reservations(agent);
      if (at_location) state.reserved_location = action.target;
      const scenario::Location& location = model_->locations[action.target];
      go_to(agent, core::compose(location.pose, action.pose), location.radius, true);
      return true;
    }
    case Kind::go_to_social_space: {
      const auto& slots = model_->social_spaces[action.target].slots;
      for (std::size_t slot = 0; slot < slots.size(); ++slot) {
        if (!slot_free(action.target, static_cast<int>(slot), agent)) continue;
        release_reservations(agent);
        state.reserved_space = action.target;
        state.reserved_slot = static_cast<int>(slot);
        go_to(agent, slots[slot], scenario::kDefaultGoalRadius, true);
        return true;
      }
      return false;  // full: try again next tick
    }
    case Kind::go_to_pose:
      release_reservations(agent);
      go_to(agent, action.pose, action.radius, true);
      return true;
    case Kind::wait_duration:
      state.wait_until_tick = state_.tick + ticks(action.value);
      return true;
    case Kind::look_at_angle:
    case Kind::turn_to:
      state.target_heading = core::wrap_angle(action.value);
      return true;
    case Kind::turn_by:
      state.target_heading = core::wrap_angle(state.heading + action.value);
      return true;
    case Kind::look_at_location:
      state.target_heading = direction_to(state.position, model_->locations[action.target].pose.position());
      return true;
    case Kind::look_at_agent:
      state.look_at_agent = action.target;
      state.target_heading = direction_to(state.position, state_.agents[action.target].position);
      return true;
    case Kind::publish:
      state_.topics[action.topic] = action.message;
      state_.inbox.push_back({action.topic, action.message});
      emit("publish", model_->agents[agent].id, {{"topic", action.topic}, {"message", action.message}});
      return true;
    case Kind::form_group:
      state_.groups[action.target] = action.members;
      emit("group_formed", model_->groups[action.target].name, {{"members", action.members.size()}});
      return true;
    case Kind::dismantle_group:
      state_.groups[action.target].clear();
      emit("group_dismantled", model_->groups[action.target].name);
      return true;
    case Kind::harass:
      release_reservations(agent);
      state.hold.reset();
      state.harass_robot = action.target;
      state.harass_distance = action.radius;
      state.wait_until_tick = state_.tick + ticks(action.value);
      return true;
    case Kind::stop_and_look:
      state.watched_robot = action.target;
      state.watch_distance = action.radius;
      state.watch_until_tick = state_.tick + ticks(action.value);
      return true;
    case Kind::request: {
      const std::int64_t id = state_.next_request_id;
      make_request(agent, action.target);
      // A request nobody can answer by design is dropped at once and leaves nothing to wait for.
      const bool open = std::any_of(state_.requests.begin(), state_.requests.end(), [&](const OpenRequest& r) { return r.id == id; });
      state.awaited_request = open ? id : 0;
      return true;
    }
    case Kind::play_motion:
      state.motion = humans::builtin_motion(action.motion);
      state.motion_tick = state_.tick;
      state.motion_released_tick = -1;
      state.wait_until_tick = state_.tick + ticks(action.value);
      return true;
    case Kind::wait_message:
    case Kind::run_task:
      return true;
  }
  return true;
}

bool Session::action_done(int agent, const Action& action) {
  const AgentState& state = state_.agents[agent];
  if (state.follow_leader >= 0) {
    // Done when the leader has arrived and this member stands at its spot beside it.
    const AgentState& leader = state_.agents[state.follow_leader];
    const bool leader_arrived = !leader.navigating && !leader.target_heading;
    return leader_arrived && (formation_target(agent) - state.position).norm() <= kHoldTolerance;
  }
  switch (action.kind) {
    case Kind::go_to_location:
    case Kind::go_to_social_space:
    case Kind::go_to_pose:
      return !state.navigating && !state.target_heading;
    case Kind::wait_duration:
      return state_.tick >= state.wait_until_tick;
    case Kind::wait_message: {
      const auto found = state_.topics.find(action.topic);
      return found != state_.topics.end() && found->second == action.message;
    }
    case Kind::look_at_angle:
    case Kind::look_at_agent:
    case Kind::look_at_location:
    case Kind::turn_by:
    case Kind::turn_to:
      return !state.target_heading;
    case Kind::harass:
    case Kind::play_motion:
      return state_.tick >= state.wait_until_tick;
    case Kind::request:
      return std::none_of(state_.requests.begin(), state_.requests.end(),
                          [&](const OpenRequest& open) { return open.id == state.awaited_request; });
    case Kind::publish:
    case Kind::run_task:
    case Kind::form_group:
    case Kind::dismantle_group:
    case Kind::stop_and_look:
      return true;
  }
  return true;
}

Vec2 Session::formation_target(int agent) const {
  const AgentState& state = state_.agents[agent];
  const AgentState& leader = state_.agents[state.follow_leader];
  const double heading = leader.velocity.norm() > 0.05 ? std::atan2(leader.velocity.y(), leader.velocity.x()) : leader.heading;
  const Pose2 spot = core::compose({leader.position.x(), leader.position.y(), heading},
                                   {state.formation_offset.x(), state.formation_offset.y(), 0.0});
  return spot.position();
}

void Session::finish_action(int agent) {
  AgentState& state = state_.agents[agent];
  state.program.pop_front();
  state.action_started = false;
  state.look_at_agent = -1;
  state.harass_robot = -1;
  if (state.follow_leader >= 0) {
    state.hold = state.position;
    state.target_heading = state_.agents[state.follow_leader].heading;
    state.follow_leader = -1;
  }
  if (state.program.empty()) state.answering_request = false;
}

void Session::release_reservations(int agent) {
  AgentState& state = state_.agents[agent];
  state.reserved_location = -1;
  state.reserved_space = -1;
  state.reserved_slot = -1;
}

bool Session::slot_free(int space, int slot, int agent) const {
  const Vec2 position = model_->social_spaces[space].slots[slot].position();
  for (std::size_t other = 0; other < state_.agents.size(); ++other) {
    const AgentState& state = state_.agents[other];
    if (static_cast<int>(other) == agent || !state.active) continue;
    if (state.reserved_space == space) {
      // Someone holding another slot of this space stands for that slot, even when pushed near this one.
      if (state.reserved_slot == slot) return false;
      continue;
    }
    if ((state.position - position).norm() < 2.0 * model_->agents[other].radius) return false;
  }
  return true;
}

void Session::go_to(int agent, const Pose2& goal, double radius, bool with_heading) {
  AgentState& state = state_.agents[agent];
  state.navigating = true;
  state.hold.reset();
  state.goal = goal.position();
  state.goal_radius = radius;
  state.goal_heading = with_heading ? std::optional<double>(goal.theta) : std::nullopt;
  state.target_heading.reset();
  state.replan_at_tick = -1;
  plan_path(agent);
}

bool Session::plan_path(int agent) {
  AgentState& state = state_.agents[agent];
  const double radius = model_->agents[agent].radius;
  const auto path = model_->planner.plan(state.position, state.goal, radius, blocked_door_cells(radius), planning_history_);
  state.path_index = 0;
  state.leg_start = state.position;
  state.planned_tick = state_.tick;
  if (path) {
    state.path = *path;
    state.replan_at_tick = -1;
    return true;
  }
  state.path.clear();
  if (state.replan_at_tick < 0) {
    emit("goal_unreachable", model_->agents[agent].id, {{"x", state.goal.x()}, {"y", state.goal.y()}});
  }
  state.replan_at_tick = state_.tick + ticks(kReplanRetry);
  return false;
}

void Session::advance_body(AgentState& state, double turned) const {
  const double speed = state.velocity.norm();
  state.turn_rate = turned / model_->dt;
  const humans::MotionClip& walk = *humans::builtin_motion("walk");
  state.gait_distance = std::fmod(state.gait_distance + speed * model_->dt + humans::kTurnStepRadius * std::abs(turned), walk.speed() * walk.duration());
  if (!state.motion) return;
  const bool playing = !state.program.empty() && state.action_started && action_of(state.program.front()).kind == Kind::play_motion;
  if (state.motion_released_tick < 0 && !playing && speed > kMotionReleaseSpeed) state.motion_released_tick = state_.tick;
  if (state.motion_released_tick >= 0 && static_cast<double>(state_.tick - state.motion_released_tick) * model_->dt >= humans::kMotionBlendTime) {
    state.motion = nullptr;
    state.motion_released_tick = -1;
  }
}

humans::Activity Session::activity(int agent) const {
  const AgentState& state = state_.agents[agent];
  humans::Activity activity;
  activity.time = time();
  activity.gait_distance = state.gait_distance;
  activity.speed = state.velocity.norm();
  activity.turn_rate = state.turn_rate;
  activity.motion = state.motion;
  if (state.motion) {
    const std::int64_t until = state.motion_released_tick >= 0 ? state.motion_released_tick : state_.tick;
    activity.motion_time = static_cast<double>(until - state.motion_tick) * model_->dt;
    if (state.motion_released_tick >= 0) activity.since_release = static_cast<double>(state_.tick - state.motion_released_tick) * model_->dt;
  }
  return activity;
}

humans::BodyCapsules Session::human_body(int agent) const {
  const AgentState& state = state_.agents[agent];
  // The physics world, each laser scan and each camera ask for the same bodies within a tick.
  CachedBody& cached = body_cache_[agent];
  if (cached.tick == state_.tick && cached.position == state.position && cached.heading == state.heading) return cached.body;
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.translation() = Eigen::Vector3d(state.position.x(), state.position.y(), 0.0);
  base.linear() = Eigen::AngleAxisd(state.heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const humans::Skeleton& skeleton = *skeletons_[agent];
  cached = {state_.tick, state.position, state.heading,
            humans::body_capsules(skeleton, humans::forward_kinematics(skeleton, humans::body_pose(activity(agent)), base))};
  return cached.body;
}

void Session::locomotion() {
  crowd_members_.clear();
  for (std::size_t i = 0; i < state_.agents.size(); ++i) {
    if (state_.agents[i].active) crowd_members_.push_back(i);
  }
  crowd_agents_.resize(crowd_members_.size());
  watching_headings_.assign(state_.agents.size(), std::nullopt);
  for (std::size_t k = 0; k < crowd_members_.size(); ++k) {
    const std::size_t i = crowd_members_[k];
    AgentState& state = state_.agents[i];
    const scenario::AgentDef& def = model_->agents[i];
    Vec2 preferred = Vec2::Zero();
    std::optional<double>& watching_heading = watching_headings_[i];
    if (state.navigating) {
      if (state.path.empty() && state_.tick >= state.replan_at_tick) plan_path(static_cast<int>(i));
      if (!state.path.empty() && state_.tick - state.planned_tick >= ticks(kReplanInterval)) {
        // Pushed too far off the leg by avoidance: rejoin the path from here without a search when a
        // straight way is free (local avoidance keeps the agent off the walls), else plan again.
        const Vec2& waypoint = state.path[state.path_index];
        const Vec2 nearest = core::closest_point_on_segment(state.position, state.leg_start, waypoint);
        if ((nearest - state.position).norm() > model_->replan_distance) {
          const double radius = model_->agents[i].radius;
          const double clearance = kRejoinClearance * radius;
          const world::Rejoin rejoin = model_->planner.rejoin(state.position, state.leg_start, waypoint, clearance,
                                                               blocked_door_cells(clearance));
          state.planned_tick = state_.tick;
          if (rejoin == world::Rejoin::replan) {
            plan_path(static_cast<int>(i));
          } else {
            if (rejoin == world::Rejoin::back_to_corner) {
              state.path.insert(state.path.begin() + static_cast<std::ptrdiff_t>(state.path_index), state.leg_start);
            }
            state.leg_start = state.position;
          }
        }
      }
      while (state.path_index + 1 < state.path.size() &&
             (state.path[state.path_index] - state.position).norm() < kWaypointReached) {
        state.leg_start = state.path[state.path_index];
        ++state.path_index;
      }
      const double to_goal = (state.goal - state.position).norm();
      if (to_goal <= state.goal_radius) {
        state.navigating = false;
        state.path.clear();
        state.hold = state.goal;
        if (state.goal_heading) state.target_heading = core::wrap_angle(*state.goal_heading);
      } else if (!state.path.empty()) {
        const Vec2 target = state.path[state.path_index];
        const bool last = state.path_index + 1 == state.path.size();
        const double speed = state.preferred_speed * (last ? std::clamp(to_goal / kArrivalSlowdown, 0.3, 1.0) : 1.0);
        preferred = (target - state.position).normalized() * speed;
      }
    }
    if (state.follow_leader >= 0) {
      const Vec2 to_spot = formation_target(static_cast<int>(i)) - state.position;
      const double speed = std::min(state.preferred_speed * humans::kMaxSpeedFactor, to_spot.norm() / kArrivalSlowdown * state.preferred_speed);
      preferred = to_spot.norm() > 1e-9 ? Vec2(to_spot.normalized() * speed) : Vec2::Zero();
    }
    if (state.harass_robot >= 0) {
      const AgentState& robot = state_.agents[state.harass_robot];
      const Vec2 in_the_way = robot.position + core::heading_vector(robot.heading) * state.harass_distance;
      const Vec2 to_spot = in_the_way - state.position;
      preferred = to_spot.norm() > 0.1 ? Vec2(to_spot.normalized() * std::min(state.preferred_speed, to_spot.norm() / kArrivalSlowdown * state.preferred_speed))
                                      : Vec2::Zero();
      state.target_heading = direction_to(state.position, robot.position);
    }
    if (state.watched_robot >= 0 && state_.tick < state.watch_until_tick) {
      const Vec2 robot = state_.agents[state.watched_robot].position;
      if ((robot - state.position).norm() <= state.watch_distance) {
        preferred = Vec2::Zero();
        watching_heading = direction_to(state.position, robot);
      }
    }
    if (!state.navigating && state.hold) {
      // Pushed aside while standing (making way in a queue): step back to the spot.
      const Vec2 back = *state.hold - state.position;
      if (back.norm() > kHoldTolerance) preferred = back.normalized() * std::min(kHoldSpeed, state.preferred_speed);
    }
    if (state.look_at_agent >= 0) {
      state.target_heading = direction_to(state.position, state_.agents[state.look_at_agent].position);
    }
    humans::CrowdAgent& crowd = crowd_agents_[k];
    crowd.position = state.position;
    crowd.radius = def.radius;
    crowd.avoidance = def.avoidance;
    crowd.controlled = def.kind == AgentKind::robot || state.rooted;  // a controlled agent keeps its velocity
    crowd.preferred_velocity = preferred;
    crowd.max_speed = std::max(state.preferred_speed * humans::kMaxSpeedFactor, 1e-3);
    crowd.velocity = !crowd.controlled ? state.velocity
                     : state.rooted ? Vec2::Zero()
                     : runtime_of_agent_[i] >= 0 ? state.velocity  // where its base is taking it
                     : state.navigating ? preferred : state.commanded_velocity;
  }
  const humans::ObstacleQuery obstacles = [this](const Vec2& p, double range) -> std::optional<Vec2> {
    std::optional<Vec2> nearest = model_->field.nearest_obstacle(model_->grid, p);
    for (std::size_t d = 0; d < model_->doors.size(); ++d) {
      if (!door_blocks(static_cast<int>(d))) continue;
      const scenario::Door& door = model_->doors[d];
      const Vec2 on_door = core::closest_point_on_segment(p, door.from, door.to);
      if (!nearest || (on_door - p).norm() < (*nearest - p).norm()) nearest = on_door;
    }
    if (!nearest || (*nearest - p).norm() > range) return std::nullopt;
    return nearest;
  };
  crowd_.compute_velocities(crowd_agents_, obstacles, model_->dt, velocities_);

  const double max_turn = kTurnRate * model_->dt;
  for (std::size_t k = 0; k < crowd_members_.size(); ++k) {
    const std::size_t i = crowd_members_[k];
    if (runtime_of_agent_[i] >= 0) continue;  // a robot with a model moves by its own base
    AgentState& state = state_.agents[i];
    state.velocity = velocities_[k];
    state.position += state.velocity * model_->dt;
    const double heading_before = state.heading;
    std::optional<double> desired = watching_headings_[i] ? watching_headings_[i] : state.target_heading;
    // Walking direction, for every walker every step: the polynomial (1e-5 rad) spares a libm call.
    if (!desired && state.velocity.norm() > 0.05) desired = core::polynomial_atan2(state.velocity.y(), state.velocity.x());
    if (desired) {
      const double difference = core::wrap_angle(*desired - state.heading);
      if (std::abs(difference) <= max_turn) {
        state.heading = core::wrap_angle(*desired);
        if (!watching_headings_[i] && state.target_heading && std::abs(difference) <= kHeadingTolerance) {
          state.target_heading.reset();
        }
      } else {
        state.heading = core::wrap_angle(state.heading + std::copysign(max_turn, difference));
      }
    }
    if (model_->agents[i].kind == AgentKind::human) advance_body(state, core::wrap_angle(state.heading - heading_before));
  }
}

void Session::decide_robots() {
  for (RobotRuntime& runtime : robots_) {
    if (!runtime.robot.description().drive || !state_.agents[runtime.agent].active) continue;
    const AgentState& state = state_.agents[runtime.agent];
    const Pose2 pose = runtime.robot.pose();
    robots::Twist command = runtime.command;  // teleoperation, or an external controller
    if (runtime.controller.kind == scenario::RobotController::Kind::teleop) {
      // Under external control: its commands drive the robot, even along a choreography's goto.
    } else if (state.navigating && !state.path.empty()) {
      const std::vector<Vec2> path(state.path.begin() + static_cast<std::ptrdiff_t>(state.path_index), state.path.end());
      if (runtime.controller.kind == scenario::RobotController::Kind::social) {
        std::vector<Vec2> people;
        for (std::size_t other = 0; other < state_.agents.size(); ++other) {
          if (state_.agents[other].active && model_->agents[other].kind == AgentKind::human) people.push_back(state_.agents[other].position);
        }
        command = follow_velocity(pose, social_velocity(pose, path, state.preferred_speed, people, model_->agents[runtime.agent].radius));
      } else {
        command = pure_pursuit(pose, path, state.preferred_speed);
      }
    } else if (state.target_heading) {
      // Turning on the spot to a goal's heading or to look at something.
      command = {0.0, kHeadingGain * core::wrap_angle(*state.target_heading - pose.theta)};
    } else {
      command = {};
    }
    runtime.robot.command_base(command);
  }
}

void Session::move_robots() {
  for (RobotRuntime& runtime : robots_) {
    AgentState& state = state_.agents[runtime.agent];
    if (!state.active) continue;
    const bool was_navigating = state.navigating;
    runtime.robot.step(runtime.motor_random);
    const Pose2& pose = runtime.robot.pose();
    state.position = pose.position();
    state.heading = pose.theta;
    state.velocity = core::heading_vector(pose.theta) * runtime.robot.twist().linear;
    if (state.target_heading && std::abs(core::wrap_angle(*state.target_heading - pose.theta)) <= kHeadingTolerance) {
      state.target_heading.reset();
    }
    if (was_navigating && runtime.controller.goal && (state.goal - state.position).norm() <= state.goal_radius &&
        (*runtime.controller.goal).position() == state.goal) {
      emit("robot_goal_reached", model_->agents[runtime.agent].id, {{"x", state.position.x()}, {"y", state.position.y()}});
    }
  }
}

void Session::command_robot_joints(AgentId robot, const std::string& group, const std::vector<double>& targets, bool velocities) {
  const int agent = index_of(robot);
  if (runtime_of_agent_[agent] < 0) throw core::Error(core::ErrorCode::conflict, "agent '" + model_->agents[agent].id + "' is not a robot with a model");
  robots_[runtime_of_agent_[agent]].robot.command_group(group, targets, velocities);
}

void Session::command_robot_gripper(AgentId robot, bool closed) {
  const int agent = index_of(robot);
  if (runtime_of_agent_[agent] < 0) throw core::Error(core::ErrorCode::conflict, "agent '" + model_->agents[agent].id + "' is not a robot with a model");
  robots_[runtime_of_agent_[agent]].robot.set_gripper(closed);
}

Eigen::Isometry3d Session::object_pose(int object) const {
  if (object < 0 || object >= static_cast<int>(object_bodies_.size())) {
    throw core::Error(core::ErrorCode::not_found, "no object " + std::to_string(object));
  }
  return physics_->pose(object_bodies_[object]);
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
  state.target_heading.reset();
  if (state.navigating) {
    state.path.clear();  // planned again from here on the next step
    state.replan_at_tick = -1;
  } else {
    state.hold = at;
  }
  if (const int runtime = runtime_of_agent_[agent]; runtime >= 0) robots_[runtime].robot.set_pose({at.x(), at.y(), state.heading});
  emit("placed", model_->agents[agent].id, {{"x", at.x()}, {"y", at.y()}, {"theta", state.heading}});
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
  const int body = object_bodies_[object];
  if (physics_->holder(body) >= 0) {
    throw core::Error(core::ErrorCode::conflict, "object '" + model_->objects[object].name + "' is held by a gripper");
  }
  physics_->place(body, pose);
  emit("placed", model_->objects[object].name, {{"x", pose.translation().x()}, {"y", pose.translation().y()}, {"z", pose.translation().z()}});
}

namespace {

/// A capsule of the body as the physics world's shape: centred, its axis along z (about which it is
/// round, so any x and y across it do).
Eigen::Isometry3d capsule_pose(const humans::Capsule& capsule) {
  const Eigen::Vector3d z = (capsule.to - capsule.from).normalized();
  const Eigen::Vector3d x = (std::abs(z.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY()).cross(z).normalized();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() << x, z.cross(x), z;
  pose.translation() = 0.5 * (capsule.from + capsule.to);
  return pose;
}

Eigen::Isometry3d upright(const Vec2& position, double z) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translate(Eigen::Vector3d(position.x(), position.y(), z));
  return pose;
}

robots::Shape capsule(double radius, double length) {
  robots::Shape shape;
  shape.kind = robots::Shape::Kind::capsule;
  shape.radius = radius;
  shape.length = length;
  return shape;
}

}  // namespace

void Session::build_physics() {
  using physics::BodyOwner;
  physics_ = std::make_unique<physics::PhysicsWorld>(model_->dt);
  // The map: an image's outline as walls, or each obstacle (walls included) as a prism of its height.
  physics_->add_floor_and_walls(model_->map_from_image ? std::span<const world::Segment>(model_->outline) : std::span<const world::Segment>(),
                                scenario::kDefaultObstacleHeight);
  if (!model_->map_from_image) {
    for (const scenario::Obstacle& obstacle : model_->obstacles) {
      physics_->add_static_prism(obstacle.polygon, obstacle.height, {BodyOwner::Kind::map, -1, obstacle.name});
    }
  }
  for (std::size_t d = 0; d < model_->doors.size(); ++d) {
    const scenario::Door& door = model_->doors[d];
    robots::Shape slab;
    slab.size = Eigen::Vector3d(door.width(), door.thickness, scenario::kDefaultObstacleHeight);
    Eigen::Isometry3d pose = upright(0.5 * (door.from + door.to), 0.5 * scenario::kDefaultObstacleHeight);
    pose.rotate(Eigen::AngleAxisd(direction_to(door.from, door.to), Eigen::Vector3d::UnitZ()));
    door_bodies_.push_back(physics_->add_kinematic(slab, pose, {BodyOwner::Kind::map, -1, door.name}));
    physics_->set_enabled(door_bodies_.back(), door_blocks(static_cast<int>(d)));
  }
  std::array<int, humans::kBodyPartCount> no_bodies;
  no_bodies.fill(-1);
  human_bodies_.assign(state_.agents.size(), no_bodies);
  for (std::size_t i = 0; i < state_.agents.size(); ++i) {
    if (model_->agents[i].kind != AgentKind::human) continue;
    const int agent = static_cast<int>(i);
    // Bone lengths do not change, so each capsule keeps the length it has now.
    const humans::BodyCapsules body = human_body(agent);
    for (int part = 0; part < humans::kBodyPartCount; ++part) {
      const humans::Capsule& solid = body[part];
      human_bodies_[i][part] = physics_->add_kinematic(capsule(solid.radius, (solid.to - solid.from).norm()), capsule_pose(solid),
                                                       {BodyOwner::Kind::human, agent, std::string(humans::body_part_name(static_cast<humans::BodyPart>(part)))});
    }
  }
  disc_robot_bodies_.assign(state_.agents.size(), -1);
  for (std::size_t i = 0; i < state_.agents.size(); ++i) {
    const scenario::AgentDef& def = model_->agents[i];
    if (def.kind != AgentKind::robot || def.robot_model) continue;
    robots::Shape disc;
    disc.kind = robots::Shape::Kind::cylinder;
    disc.radius = def.radius;
    disc.length = kDiscRobotHeight;
    disc_robot_bodies_[i] = physics_->add_kinematic(disc, upright(state_.agents[i].position, 0.5 * kDiscRobotHeight),
                                                    {BodyOwner::Kind::robot, static_cast<int>(i), "body"});
  }
  for (RobotRuntime& runtime : robots_) {
    const robots::RobotDescription& description = runtime.robot.description();
    const auto poses = runtime.robot.link_poses();
    for (std::size_t l = 0; l < description.links.size(); ++l) {
      const robots::Link& link = description.links[l];
      runtime.link_bodies.push_back(link.collision ? physics_->add_kinematic(*link.collision, poses[l] * robots::to_isometry(link.collision_origin),
                                                                             {BodyOwner::Kind::robot, runtime.agent, link.name})
                                                   : -1);
    }
  }
  for (std::size_t o = 0; o < model_->objects.size(); ++o) {
    const scenario::MovableObject& object = model_->objects[o];
    object_bodies_.push_back(physics_->add_dynamic(object.shape, object.mass, robots::to_isometry(object.pose),
                                                   {BodyOwner::Kind::object, static_cast<int>(o), object.name}));
  }
}

void Session::step_physics() {
  for (std::size_t d = 0; d < door_bodies_.size(); ++d) physics_->set_enabled(door_bodies_[d], door_blocks(static_cast<int>(d)));
  // People touch robots only: a body far from every robot is left out of the world, which spares
  // Bullet most of its kinematic bodies in a crowd.
  std::vector<Vec2> robots_at;
  for (std::size_t i = 0; i < state_.agents.size(); ++i) {
    if (state_.agents[i].active && model_->agents[i].kind == AgentKind::robot) robots_at.push_back(state_.agents[i].position);
  }
  for (std::size_t i = 0; i < human_bodies_.size(); ++i) {
    const auto& bodies = human_bodies_[i];
    if (bodies[0] < 0) continue;
    const AgentState& agent = state_.agents[i];
    const bool near_a_robot = std::any_of(robots_at.begin(), robots_at.end(), [&](const Vec2& robot) {
      return (robot - agent.position).squaredNorm() <= kHumanContactRange * kHumanContactRange;
    });
    const bool present = agent.active && near_a_robot;
    if (present) {
      const humans::BodyCapsules body = human_body(static_cast<int>(i));
      for (int part = 0; part < humans::kBodyPartCount; ++part) physics_->set_kinematic_pose(bodies[part], capsule_pose(body[part]));
    }
    for (const int part : bodies) physics_->set_enabled(part, present);
  }
  for (std::size_t i = 0; i < disc_robot_bodies_.size(); ++i) {
    if (disc_robot_bodies_[i] < 0) continue;
    physics_->set_enabled(disc_robot_bodies_[i], state_.agents[i].active);
    physics_->set_kinematic_pose(disc_robot_bodies_[i], upright(state_.agents[i].position, 0.5 * kDiscRobotHeight));
  }
  for (RobotRuntime& runtime : robots_) {
    const bool active = state_.agents[runtime.agent].active;
    for (const int body : runtime.link_bodies) {
      if (body >= 0) physics_->set_enabled(body, active);
    }
    if (!active) {
      if (runtime.held_object >= 0) physics_->detach(object_bodies_[runtime.held_object]);  // it drops what it held
      runtime.held_object = -1;
      continue;
    }
    const auto poses = runtime.robot.link_poses();
    const auto& links = runtime.robot.description().links;
    for (std::size_t l = 0; l < links.size(); ++l) {
      if (runtime.link_bodies[l] >= 0) physics_->set_kinematic_pose(runtime.link_bodies[l], poses[l] * robots::to_isometry(links[l].collision_origin));
    }
  }
  physics_->step();
  const auto touching = physics_->touching();
  auto touch = [&](int a, int b) {
    return std::binary_search(touching.begin(), touching.end(), std::pair{std::min(a, b), std::max(a, b)});
  };
  // Grasping: a closed gripper holds an object both its fingers touch, until it opens.
  for (RobotRuntime& runtime : robots_) {
    const robots::RobotDescription& description = runtime.robot.description();
    if (!description.gripper) continue;
    const std::string& id = model_->agents[runtime.agent].id;
    if (runtime.held_object >= 0 && !runtime.robot.gripper_closed()) {
      physics_->detach(object_bodies_[runtime.held_object]);
      emit("release", id, {{"object", model_->objects[runtime.held_object].name}});
      runtime.held_object = -1;
    }
    if (runtime.held_object >= 0 || !runtime.robot.gripper_closed()) continue;
    const robots::Joint& motor = description.joints[description.find_joint(description.gripper->joint)];
    std::vector<int> fingers;
    for (const int joint : description.finger_joints()) fingers.push_back(runtime.link_bodies[description.find_link(description.joints[joint].child)]);
    const int palm = runtime.link_bodies[description.find_link(motor.parent)];
    for (std::size_t o = 0; o < object_bodies_.size() && palm >= 0; ++o) {
      if (physics_->holder(object_bodies_[o]) >= 0) continue;
      const bool gripped = fingers.size() >= 2 && std::all_of(fingers.begin(), fingers.end(), [&](int finger) {
                             return finger >= 0 && touch(finger, object_bodies_[o]);
                           });
      if (!gripped) continue;
      physics_->attach(object_bodies_[o], palm);
      runtime.held_object = static_cast<int>(o);
      emit("grasp", id, {{"object", model_->objects[o].name}});
      break;
    }
  }
}

sensors::RayScene Session::range_scene(double height, int robot_agent) const {
  sensors::RayScene scene(model_->outline, height);
  for (std::size_t d = 0; d < model_->doors.size(); ++d) {
    if (!door_blocks(static_cast<int>(d))) continue;
    const scenario::Door& door = model_->doors[d];
    std::vector<world::Segment> edges;
    const Vec2 across = core::left_normal((door.to - door.from).normalized()) * (0.5 * door.thickness);
    world::append_edges({door.from - across, door.to - across, door.to + across, door.from + across}, edges);
    for (const world::Segment& edge : edges) scene.add(edge);
  }
  for (std::size_t o = 0; o < object_bodies_.size(); ++o) {
    // Movable objects as their footprint at this height, taken upright (a lying cup reads as standing).
    const scenario::MovableObject& object = model_->objects[o];
    const Eigen::Isometry3d pose = physics_->pose(object_bodies_[o]);
    const robots::Shape& shape = object.shape;
    const double half_height = shape.kind == robots::Shape::Kind::box      ? 0.5 * shape.size.z()
                               : shape.kind == robots::Shape::Kind::sphere ? shape.radius
                                                                            : 0.5 * shape.length + (shape.kind == robots::Shape::Kind::capsule ? shape.radius : 0.0);
    if (std::abs(pose.translation().z() - height) > half_height) continue;
    const Vec2 centre(pose.translation().x(), pose.translation().y());
    if (shape.kind != robots::Shape::Kind::box) {
      scene.add(sensors::Circle{centre, shape.radius});
      continue;
    }
    const Eigen::Vector3d x_axis = pose.rotation().col(0);
    const Vec2 along = Vec2(x_axis.x(), x_axis.y()).normalized();
    const Vec2 u = 0.5 * shape.size.x() * along, v = 0.5 * shape.size.y() * core::left_normal(along);
    std::vector<world::Segment> edges;
    world::append_edges({centre - u - v, centre + u - v, centre + u + v, centre - u + v}, edges);
    for (const world::Segment& edge : edges) scene.add(edge);
  }
  for (std::size_t i = 0; i < state_.agents.size(); ++i) {
    const AgentState& agent = state_.agents[i];
    if (!agent.active || static_cast<int>(i) == robot_agent) continue;
    const scenario::AgentDef& def = model_->agents[i];
    if (def.kind == AgentKind::human) {
      add_human_body(scene, human_body(static_cast<int>(i)), height);
    } else if (!def.robot_model || height < def.robot_model->height) {
      scene.add(sensors::Circle{agent.position, def.radius});
    }
  }
  return scene;
}

void Session::sense() {
  for (RobotRuntime& runtime : robots_) {
    if (!state_.agents[runtime.agent].active) continue;
    const std::string& id = model_->agents[runtime.agent].id;
    if (runtime.robot.description().drive) {
      runtime.odometry.update(runtime.robot.twist(), model_->dt, runtime.sensor_random);
      if (due(runtime.odometry_schedule, state_.tick, model_->dt)) {
        runtime.odometry_reading = {state_.tick, runtime.odometry.pose(), runtime.odometry.twist()};
      }
    }
    for (RobotRuntime::LaserSensor& sensor : runtime.lasers) {
      if (!due(sensor.schedule, state_.tick, model_->dt)) continue;
      const Eigen::Isometry3d mount = runtime.robot.sensor_pose(*sensor.mount);
      const Vec2 origin(mount.translation().x(), mount.translation().y());
      const Eigen::Vector3d forward = mount.rotation().col(0);
      const double heading = std::atan2(forward.y(), forward.x());
      const sensors::RayScene scene = range_scene(mount.translation().z(), runtime.agent);
      sensor.laser.scan(scene, origin, heading, runtime.sensor_random, sensor.reading.ranges);
      sensor.reading.tick = state_.tick;
      sensor.reading.pose = {origin.x(), origin.y(), heading};
      sensor.reading.height = mount.translation().z();
    }
    if (runtime.people_detector && due(runtime.people_schedule, state_.tick, model_->dt)) {
      // The detector looks from the first laser's mount (else the base centre) at torso height.
      Pose2 from = runtime.robot.pose();
      if (!runtime.lasers.empty()) {
        const Eigen::Isometry3d mount = runtime.robot.sensor_pose(*runtime.lasers.front().mount);
        const Eigen::Vector3d forward = mount.rotation().col(0);
        from = {mount.translation().x(), mount.translation().y(), std::atan2(forward.y(), forward.x())};
      }
      const sensors::RayScene scene = range_scene(kPeopleDetectorHeight, runtime.agent);
      std::vector<sensors::PersonTruth> people;
      for (std::size_t i = 0; i < state_.agents.size(); ++i) {
        if (state_.agents[i].active && model_->agents[i].kind == AgentKind::human) {
          people.push_back({static_cast<int>(i), state_.agents[i].position, state_.agents[i].velocity, kPersonRadius});
        }
      }
      runtime.people_detector->detect(scene, from.position(), from.theta, people, runtime.sensor_random, runtime.people.people);
      runtime.people.tick = state_.tick;
    }
    // Bumper: what the robot's links touch in the physics world (the floor does not count).
    std::vector<Contact> contacts;
    for (const auto& [first, second] : physics_->touching()) {
      const physics::BodyOwner& a = physics_->owner(first);
      const physics::BodyOwner& b = physics_->owner(second);
      const bool mine_first = a.kind == physics::BodyOwner::Kind::robot && a.index == runtime.agent;
      const bool mine_second = b.kind == physics::BodyOwner::Kind::robot && b.index == runtime.agent;
      if (mine_first == mine_second) continue;  // not this robot's, or two of its own links
      const physics::BodyOwner& other = mine_first ? b : a;
      if (other.kind == physics::BodyOwner::Kind::map && other.part == "floor") continue;
      Contact contact;
      if (other.kind == physics::BodyOwner::Kind::human || other.kind == physics::BodyOwner::Kind::robot) contact.agent = other.index;
      if (other.kind == physics::BodyOwner::Kind::object) contact.object = other.index;
      contact.part = other.part;
      if (std::find(contacts.begin(), contacts.end(), contact) == contacts.end()) contacts.push_back(contact);
    }
    const auto with = [&](const Contact& contact) -> std::string {
      if (contact.agent >= 0) return model_->agents[contact.agent].id;
      if (contact.object >= 0) return model_->objects[contact.object].name;
      return "map";
    };
    for (const Contact& contact : contacts) {
      if (std::find(runtime.contacts.begin(), runtime.contacts.end(), contact) == runtime.contacts.end()) {
        emit("contact_start", id, {{"with", with(contact)}, {"part", contact.part}});
      }
    }
    for (const Contact& contact : runtime.contacts) {
      if (std::find(contacts.begin(), contacts.end(), contact) == contacts.end()) {
        emit("contact_end", id, {{"with", with(contact)}, {"part", contact.part}});
      }
    }
    runtime.contacts = std::move(contacts);
  }
}

std::string Session::state_hash_hex() const {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(state_hash()));
  return text;
}

std::uint64_t Session::state_hash() const {
  core::StateHasher hash;
  hash.add(state_.tick).add(state_.step).add(state_.finished);
  for (const AgentState& agent : state_.agents) {
    hash.add(agent.active);
    hash.add(agent.position.x()).add(agent.position.y()).add(agent.velocity.x()).add(agent.velocity.y());
    hash.add(agent.heading).add(agent.preferred_speed).add(static_cast<std::int64_t>(agent.program.size()));
    hash.add(agent.navigating).add(static_cast<std::int64_t>(agent.path_index)).add(static_cast<std::int64_t>(agent.path.size()));
    hash.add(agent.leg_start.x()).add(agent.leg_start.y());
    hash.add(agent.reserved_location).add(agent.reserved_space).add(agent.reserved_slot);
    hash.add(agent.follow_leader).add(agent.harass_robot).add(agent.watched_robot);
  }
  for (const auto& [topic, message] : state_.topics) hash.add(std::string_view(topic)).add(std::string_view(message));
  for (const auto& members : state_.groups) {
    for (int member : members) hash.add(member);
    hash.add(-1);
  }
  for (const DoorState& door : state_.doors) hash.add(static_cast<int>(door.phase)).add(door.opening);
  for (const ElevatorState& cabin : state_.elevators) {
    hash.add(static_cast<int>(cabin.phase)).add(cabin.floor).add(static_cast<std::int64_t>(cabin.queue.size()));
  }
  hash.add(static_cast<std::int64_t>(state_.requests.size())).add(static_cast<std::int64_t>(state_.events.size()));
  hash.add(static_cast<std::int64_t>(state_.commanded.size()));
  for (std::uint64_t word : state_.random.state()) hash.add(word);
  for (const AgentState& agent : state_.agents) {
    hash.add(agent.rooted);
    hash.add(agent.gait_distance);
    hash.add(agent.turn_rate);
    hash.add(agent.motion ? agent.motion->name() : std::string());
    hash.add(agent.motion_tick);
    hash.add(agent.motion_released_tick);
  }
  for (const RobotRuntime& runtime : robots_) runtime.hash(hash);
  for (const int body : object_bodies_) {
    const Eigen::Isometry3d pose = physics_->pose(body);
    for (int k = 0; k < 16; ++k) hash.add(pose.data()[k]);
  }
  return hash.value();
}

}  // namespace hrisim::sim
