#include "sim/session.hpp"

#include <algorithm>
#include <cmath>

#include "core/state_hash.hpp"

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
    } else {
      agent.preferred_speed = def.preferred_speed.value_or(kScriptedRobotSpeed);
    }
    state_.agents.push_back(std::move(agent));
  }
  state_.steps.resize(model_->steps.size());
  for (const scenario::Request& scripted : model_->requests) schedule_request(scripted.time, scripted.robot, scripted.task);
  if (!model_->steps.empty()) start_step(0);
}

void Session::schedule_request(double at, int robot, int task) {
  const ScheduledRequest request{at, robot, task};
  const auto later = std::upper_bound(state_.scheduled.begin(), state_.scheduled.end(), request,
                                      [](const ScheduledRequest& a, const ScheduledRequest& b) { return a.time < b.time; });
  state_.scheduled.insert(later, request);
}

void Session::emit(std::string kind, std::string subject, nlohmann::json data) {
  state_.events.push_back({state_.tick, time(), std::move(kind), std::move(subject), std::move(data)});
}

const Action& Session::action_of(const PendingAction& pending) const {
  return pending.task >= 0 ? model_->tasks[pending.task].actions[pending.index]
                           : model_->steps[pending.step].actions[pending.index];
}

void Session::start_step(int step) {
  state_.step = step;
  state_.steps[step].started_tick = state_.tick;
  const scenario::Step& definition = model_->steps[step];
  emit("step_started", definition.name, {{"index", step}});
  for (std::size_t i = 0; i < definition.actions.size(); ++i) {
    state_.agents[definition.actions[i].agent].program.push_back({-1, static_cast<int>(i), step});
  }
}

void Session::step() {
  if (state_.finished) return;
  while (!state_.scheduled.empty() && state_.scheduled.front().time <= time()) {
    const ScheduledRequest due = state_.scheduled.front();
    state_.scheduled.erase(state_.scheduled.begin());
    request(due.robot, due.task);
  }
  update_requests();
  update_choreography();
  if (state_.finished) return;
  locomotion();
  ++state_.tick;
  if (time() >= time_limit_) {
    state_.finished = true;
    state_.termination = "timeout";
    const bool in_step = state_.step < static_cast<int>(model_->steps.size());
    emit("time_limit", in_step ? model_->steps[state_.step].name : "", {{"step", state_.step}});
  }
}

void Session::run(std::optional<double> max_time) {
  if (max_time) time_limit_ = *max_time;
  while (!state_.finished) step();
}

void Session::request(int robot, int task) {
  const Vec2 position = state_.agents[robot].position;
  emit("request", model_->agents[robot].id,
       {{"task", model_->tasks[task].name}, {"x", position.x()}, {"y", position.y()}});
  if (std::find(model_->async_tasks.begin(), model_->async_tasks.end(), task) == model_->async_tasks.end()) {
    emit("request_dropped", model_->agents[robot].id,
         {{"task", model_->tasks[task].name}, {"reason", "the scenario has no response for this task"}});
    return;
  }
  state_.requests.push_back({robot, task, position, state_.tick, state_.tick});
}

void Session::command_robot(int robot, const Vec2& velocity) { state_.agents[robot].commanded_velocity = velocity; }

bool Session::idle(int agent) const {
  return model_->agents[agent].kind == AgentKind::human && state_.agents[agent].program.empty() &&
         !state_.agents[agent].answering_request;
}

void Session::update_requests() {
  const auto retry = static_cast<std::int64_t>(std::llround(kRequestRetryPeriod / model_->dt));
  const auto timeout = static_cast<std::int64_t>(std::llround(kRequestTimeout / model_->dt));
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
           {{"task", task_name}, {"robot", model_->agents[open.robot].id}, {"distance", chosen_distance}});
    } else if (state_.tick - open.asked_tick + retry > timeout) {
      emit("request_dropped", model_->agents[open.robot].id,
           {{"task", task_name}, {"reason", "no idle human within 3 m"}});
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
      if (!state_.finished) {
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
      if (!start_action(agent, action)) return false;
      state.action_started = true;
    }
    if (!action_done(agent, action)) return false;
    finish_action(agent);
  }
  return true;
}

bool Session::start_action(int agent, const Action& action) {
  AgentState& state = state_.agents[agent];
  switch (action.kind) {
    case Kind::go_to_location: {
      for (std::size_t other = 0; other < state_.agents.size(); ++other) {
        if (static_cast<int>(other) != agent && state_.agents[other].reserved_location == action.target) return false;
      }
      release_reservations(agent);
      state.reserved_location = action.target;
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
      state.wait_until_tick = state_.tick + static_cast<std::int64_t>(std::llround(action.value / model_->dt));
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
      emit("publish", model_->agents[agent].id, {{"topic", action.topic}, {"message", action.message}});
      return true;
    case Kind::wait_message:
    case Kind::run_task:
      return true;
  }
  return true;
}

bool Session::action_done(int agent, const Action& action) {
  const AgentState& state = state_.agents[agent];
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
    case Kind::publish:
    case Kind::run_task:
      return true;
  }
  return true;
}

void Session::finish_action(int agent) {
  AgentState& state = state_.agents[agent];
  state.program.pop_front();
  state.action_started = false;
  state.look_at_agent = -1;
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
    if (static_cast<int>(other) == agent) continue;
    const AgentState& state = state_.agents[other];
    if (state.reserved_space == space && state.reserved_slot == slot) return false;
    if ((state.position - position).norm() < 2.0 * model_->agents[other].radius) return false;
  }
  return true;
}

void Session::go_to(int agent, const Pose2& goal, double radius, bool with_heading) {
  AgentState& state = state_.agents[agent];
  state.navigating = true;
  state.goal = goal.position();
  state.goal_radius = radius;
  state.goal_heading = with_heading ? std::optional<double>(goal.theta) : std::nullopt;
  state.target_heading.reset();
  state.replan_at_tick = -1;
  plan_path(agent);
}

bool Session::plan_path(int agent) {
  AgentState& state = state_.agents[agent];
  const auto path = model_->planner.plan(state.position, state.goal, model_->agents[agent].radius);
  state.path_index = 0;
  if (path) {
    state.path = *path;
    state.replan_at_tick = -1;
    return true;
  }
  state.path.clear();
  if (state.replan_at_tick < 0) {
    emit("goal_unreachable", model_->agents[agent].id, {{"x", state.goal.x()}, {"y", state.goal.y()}});
  }
  state.replan_at_tick = state_.tick + static_cast<std::int64_t>(std::llround(kReplanRetry / model_->dt));
  return false;
}

void Session::locomotion() {
  const std::size_t n = state_.agents.size();
  crowd_agents_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    AgentState& state = state_.agents[i];
    const scenario::AgentDef& def = model_->agents[i];
    Vec2 preferred = Vec2::Zero();
    if (state.navigating) {
      if (state.path.empty() && state_.tick >= state.replan_at_tick) plan_path(static_cast<int>(i));
      if (!state.path.empty()) {
        // Pushed too far off the planned leg by avoidance: plan again from here.
        const Vec2 leg_start = state.path_index == 0 ? state.position : state.path[state.path_index - 1];
        const Vec2 nearest = core::closest_point_on_segment(state.position, leg_start, state.path[state.path_index]);
        if ((nearest - state.position).norm() > model_->replan_distance) plan_path(static_cast<int>(i));
      }
      while (state.path_index + 1 < state.path.size() &&
             (state.path[state.path_index] - state.position).norm() < kWaypointReached) {
        ++state.path_index;
      }
      const double to_goal = (state.goal - state.position).norm();
      if (to_goal <= state.goal_radius) {
        state.navigating = false;
        state.path.clear();
        if (state.goal_heading) state.target_heading = core::wrap_angle(*state.goal_heading);
      } else if (!state.path.empty()) {
        const Vec2 target = state.path[state.path_index];
        const bool last = state.path_index + 1 == state.path.size();
        const double speed = state.preferred_speed * (last ? std::clamp(to_goal / kArrivalSlowdown, 0.3, 1.0) : 1.0);
        preferred = (target - state.position).normalized() * speed;
      }
    }
    if (state.look_at_agent >= 0) {
      state.target_heading = direction_to(state.position, state_.agents[state.look_at_agent].position);
    }
    humans::CrowdAgent& crowd = crowd_agents_[i];
    crowd.position = state.position;
    crowd.radius = def.radius;
    crowd.avoidance = def.avoidance;
    crowd.controlled = def.kind == AgentKind::robot;
    crowd.preferred_velocity = preferred;
    crowd.max_speed = std::max(state.preferred_speed * humans::kMaxSpeedFactor, 1e-3);
    crowd.velocity = crowd.controlled ? (state.navigating ? preferred : state.commanded_velocity) : state.velocity;
  }
  const humans::ObstacleQuery obstacles = [this](const Vec2& p, double range) -> std::optional<Vec2> {
    const auto nearest = model_->field.nearest_obstacle(model_->grid, p);
    if (!nearest || (*nearest - p).norm() > range) return std::nullopt;
    return nearest;
  };
  crowd_.compute_velocities(crowd_agents_, obstacles, model_->dt, velocities_);

  const double max_turn = kTurnRate * model_->dt;
  for (std::size_t i = 0; i < n; ++i) {
    AgentState& state = state_.agents[i];
    state.velocity = velocities_[i];
    state.position += state.velocity * model_->dt;
    std::optional<double> desired = state.target_heading;
    if (!desired && state.velocity.norm() > 0.05) desired = std::atan2(state.velocity.y(), state.velocity.x());
    if (!desired) continue;
    const double difference = core::wrap_angle(*desired - state.heading);
    if (std::abs(difference) <= max_turn) {
      state.heading = core::wrap_angle(*desired);
      if (state.target_heading && std::abs(difference) <= kHeadingTolerance) state.target_heading.reset();
    } else {
      state.heading = core::wrap_angle(state.heading + std::copysign(max_turn, difference));
    }
  }
}

std::uint64_t Session::state_hash() const {
  core::StateHasher hash;
  hash.add(state_.tick).add(state_.step).add(state_.finished);
  for (const AgentState& agent : state_.agents) {
    hash.add(agent.position.x()).add(agent.position.y()).add(agent.velocity.x()).add(agent.velocity.y());
    hash.add(agent.heading).add(agent.preferred_speed).add(static_cast<std::int64_t>(agent.program.size()));
    hash.add(agent.navigating).add(static_cast<std::int64_t>(agent.path_index)).add(static_cast<std::int64_t>(agent.path.size()));
    hash.add(agent.reserved_location).add(agent.reserved_space).add(agent.reserved_slot);
  }
  for (const auto& [topic, message] : state_.topics) hash.add(std::string_view(topic)).add(std::string_view(message));
  hash.add(static_cast<std::int64_t>(state_.requests.size())).add(static_cast<std::int64_t>(state_.events.size()));
  for (std::uint64_t word : state_.random.state()) hash.add(word);
  return hash.value();
}

}  // namespace hrisim::sim
