#include "sim/choreography.hpp"

#include <algorithm>
#include <cmath>

#include "sim/activities.hpp"
#include "sim/carrying.hpp"
#include "sim/queues.hpp"
#include "sim/seats.hpp"
#include "sim/search.hpp"
#include "sim/sounds.hpp"
#include "sim/events.hpp"
#include "sim/walking.hpp"

namespace hrisim::sim {
namespace {

using scenario::Action;
using scenario::AgentKind;
using Kind = scenario::Action::Kind;

/// Instant actions (publish, zero waits) chained within one tick per agent, at most.
constexpr int kMaxActionsPerTick = 64;

/// Spot of member `role` of a group of `size` in the leader's frame: a pair side by side, larger
/// groups three abreast in rows behind the leader.
Vec2 formation_offset(int role, int size) {
  if (size == 2) return {0.0, -scenario::kFormationSpacing};
  static constexpr double kLateral[] = {0.0, -1.0, 1.0};
  return {-scenario::kFormationRowGap * (role / 3), kLateral[role % 3] * scenario::kFormationSpacing};
}

bool idle(const scenario::Model& model, const State& state, int agent) {
  const AgentState& a = state.agents[agent];
  return a.active && model.agents[agent].kind == AgentKind::human && a.program.empty() && !a.answering_request;
}

bool slot_free(const scenario::Model& model, const State& state, int space, int slot, int agent) {
  const Vec2 position = model.social_spaces[space].slots[slot].position();
  for (std::size_t other = 0; other < state.agents.size(); ++other) {
    const AgentState& a = state.agents[other];
    if (static_cast<int>(other) == agent || !a.active) continue;
    if (a.reservation.space.value == space) {
      // Someone holding another slot of this space stands for that slot, even when pushed near this one.
      if (a.reservation.slot.value == slot) return false;
      continue;
    }
    if ((a.position - position).norm() < 2.0 * model.agents[other].radius) return false;
  }
  return true;
}

bool start_action(const scenario::Model& model, State& state, int agent, const Action& action, const PendingAction& pending) {
  AgentState& self = state.agents[agent];
  // A follower in a group goto to a place walks in formation beside or behind the leader.
  const bool to_a_place = action.kind == Kind::go_to_location || action.kind == Kind::go_to_pose;
  if (pending.group >= 0 && pending.role > 0 && to_a_place && !state.groups[pending.group].empty()) {
    release_reservations(state, agent);
    self.navigation.hold.reset();
    self.attitude.follow_leader = AgentIndex(state.groups[pending.group].front());
    self.attitude.formation_offset = formation_offset(pending.role, pending.group_size);
    return true;
  }
  switch (action.kind) {
    case Kind::go_to_location: {
      // The location itself holds one person; a spot at an offset from it is not the location.
      const bool at_location = action.pose == Pose2{};
      for (std::size_t other = 0; other < state.agents.size() && at_location; ++other) {
        if (static_cast<int>(other) != agent && state.agents[other].reservation.location.value == action.target) return false;
      }
      release_reservations(state, agent);
      if (at_location) self.reservation.location = LocationIndex(action.target);
      const scenario::Location& location = model.locations[action.target];
      go_to(model, state, agent, core::compose(location.pose, action.pose), location.radius, true);
      return true;
    }
    case Kind::go_to_social_space: {
      const auto& slots = model.social_spaces[action.target].slots;
      for (std::size_t slot = 0; slot < slots.size(); ++slot) {
        if (!slot_free(model, state, action.target, static_cast<int>(slot), agent)) continue;
        release_reservations(state, agent);
        self.reservation.space = SpaceIndex(action.target);
        self.reservation.slot = SlotIndex(static_cast<int>(slot));
        go_to(model, state, agent, slots[slot], scenario::kDefaultGoalRadius, true);
        return true;
      }
      return false;  // full: try again next tick
    }
    case Kind::go_to_pose:
      release_reservations(state, agent);
      go_to(model, state, agent, action.pose, action.radius, true);
      return true;
    case Kind::wait_duration:
      self.wait_until_tick = state.tick + ticks(model, action.value);
      return true;
    case Kind::look_at_angle:
    case Kind::turn_to:
      self.attitude.target_heading = core::wrap_angle(action.value);
      return true;
    case Kind::turn_by:
      self.attitude.target_heading = core::wrap_angle(self.heading + action.value);
      return true;
    case Kind::look_at_location:
      self.attitude.target_heading = core::direction_to(self.position, model.locations[action.target].pose.position());
      return true;
    case Kind::look_at_object: {
      const Vec2 object = action.target >= 0 ? Vec2(state.objects[action.target].pose.translation().head<2>()) : action.pose.position();
      self.attitude.target_heading = core::direction_to(self.position, object);
      return true;
    }
    case Kind::look_at_agent:
      self.attitude.look_at_agent = AgentIndex(action.target);
      self.attitude.target_heading = core::direction_to(self.position, state.agents[action.target].position);
      return true;
    case Kind::publish:
      state.topics[action.topic] = action.message;
      state.inbox.push_back({action.topic, action.message});
      emit(model, state, model.agents[agent].id, events::Publish{action.topic, action.message});
      return true;
    case Kind::form_group:
      state.groups[action.target] = action.members;
      emit(model, state, model.groups[action.target].name, events::GroupFormed{static_cast<std::int64_t>(action.members.size())});
      return true;
    case Kind::dismantle_group:
      state.groups[action.target].clear();
      emit(model, state, model.groups[action.target].name, events::GroupDismantled{});
      return true;
    case Kind::harass:
      release_reservations(state, agent);
      self.navigation.hold.reset();
      self.attitude.harass_robot = AgentIndex(action.target);
      self.attitude.harass_distance = action.radius;
      self.wait_until_tick = state.tick + ticks(model, action.value);
      return true;
    case Kind::stop_and_look:
      self.attitude.watched_robot = AgentIndex(action.target);
      self.attitude.watch_distance = action.radius;
      self.attitude.watch_until_tick = state.tick + ticks(model, action.value);
      return true;
    case Kind::request: {
      const std::int64_t id = state.next_request_id;
      make_request(model, state, agent, action.target);
      // A request nobody can answer by design is dropped at once and leaves nothing to wait for.
      const bool open = std::any_of(state.requests.begin(), state.requests.end(), [&](const OpenRequest& r) { return r.id == id; });
      self.awaited_request = open ? id : 0;
      return true;
    }
    case Kind::say:
      start_speaking(model, state, agent, action);
      self.wait_until_tick = state.tick + ticks(model, action.value);
      return true;
    case Kind::play_motion:
      self.wait_until_tick = state.tick + ticks(model, action.value);
      if (action.motion == "stand_up" && posture_of(self) == scenario::Posture::standing) {
        self.wait_until_tick = state.tick;  // already up (off a seat too: see leaves_seat)
        return true;
      }
      self.animation.motion = humans::builtin_motion(action.motion);
      self.animation.motion_tick = state.tick;
      self.animation.motion_released_tick = -1;
      return true;
    case Kind::set_behaviour:
      self.reaction.behaviour = humans::default_behaviour(static_cast<humans::BehaviourType>(action.target));
      self.reaction.behaviour_seen = 0.0;
      self.reaction.behaviour_spent = false;
      self.reaction.reacting_to = {};
      return true;
    case Kind::sit_on:
      return start_sitting(model, state, agent, action.target);
    case Kind::join_queue:
      // Back in the line they were drawn away from (a command, a reaction): they keep their place.
      if (self.queueing.queue.value != action.target) {
        release_reservations(state, agent);
        self.queueing.queue = QueueIndex(action.target);
      }
      self.queueing.served = false;
      return true;
    case Kind::pick_up:
    case Kind::put_down:
      return start_reaching(model, state, agent, action);
    case Kind::wait_message:
    case Kind::run_routine:
    case Kind::leave:
      return true;
  }
  return true;
}

bool action_done(const State& state, int agent, const Action& action, const PendingAction& pending) {
  const AgentState& self = state.agents[agent];
  if (self.attitude.follow_leader.valid()) {
    // Done when the leader has arrived — is past this goto, not merely yet to begin it — and this
    // member stands at its spot beside it.
    const AgentState& leader = state.agents[self.attitude.follow_leader.value];
    const bool leader_past = leader.program.empty() || leader.program.front().step != pending.step ||
                             leader.program.front().routine != pending.routine || leader.program.front().index != pending.index ||
                             leader.action_started;
    const bool leader_arrived = leader_past && !leader.navigation.under_way && !leader.attitude.target_heading;
    return leader_arrived && (formation_target(state, agent) - self.position).norm() <= kHoldTolerance;
  }
  switch (action.kind) {
    case Kind::go_to_location:
    case Kind::go_to_social_space:
    case Kind::go_to_pose:
      return !self.navigation.under_way && !self.attitude.target_heading;
    case Kind::wait_duration:
      return state.tick >= self.wait_until_tick;
    case Kind::wait_message: {
      const auto found = state.topics.find(action.topic);
      return found != state.topics.end() && found->second == action.message;
    }
    case Kind::look_at_angle:
    case Kind::look_at_agent:
    case Kind::look_at_location:
    case Kind::look_at_object:
    case Kind::turn_by:
    case Kind::turn_to:
      return !self.attitude.target_heading;
    case Kind::harass:
    case Kind::play_motion:
    case Kind::say:
      return state.tick >= self.wait_until_tick;
    case Kind::sit_on:
      return sitting_done(state, agent, action.target);
    case Kind::join_queue:
      return self.queueing.served;
    case Kind::leave:
      return true;
    case Kind::pick_up:
    case Kind::put_down:
      return reaching_done(state, agent);
    case Kind::request:
      return std::none_of(state.requests.begin(), state.requests.end(), [&](const OpenRequest& open) { return open.id == self.awaited_request; });
    case Kind::publish:
    case Kind::run_routine:
    case Kind::form_group:
    case Kind::dismantle_group:
    case Kind::stop_and_look:
    case Kind::set_behaviour:
      return true;
  }
  return true;
}

void finish_action(State& state, int agent) {
  AgentState& self = state.agents[agent];
  self.program.pop_front();
  self.action_started = false;
  self.attitude.look_at_agent = {};
  self.attitude.harass_robot = {};
  self.carrying.phase = ReachPhase::none;
  self.queueing.served = false;
  if (self.attitude.follow_leader.valid()) {
    self.navigation.hold = self.position;
    self.attitude.target_heading = state.agents[self.attitude.follow_leader.value].heading;
    self.attitude.follow_leader = {};
  }
  if (self.program.empty()) self.answering_request = false;
}

/// A group running a compound task keeps together: a member begins the task's next action only once
/// every member is done with the ones before it.
bool group_ready(const State& state, int agent, const PendingAction& pending) {
  if (pending.group < 0 || pending.routine < 0) return true;
  for (const int member : state.groups[pending.group]) {
    const AgentState& other = state.agents[member];
    if (member == agent || !other.active || other.program.empty()) continue;
    const PendingAction& theirs = other.program.front();
    if (theirs.group != pending.group || theirs.step != pending.step) continue;
    if (theirs.routine == -1 || (theirs.routine == pending.routine && theirs.index < pending.index)) return false;
  }
  return true;
}

/// Works through the agent's program as far as this tick allows.
void advance_agent(const scenario::Model& model, State& state, int agent) {
  AgentState& self = state.agents[agent];
  if (!self.active) return;  // not in the scene yet (enters_at), or gone
  tend_seat(model, state, agent);
  for (int guard = 0; guard < kMaxActionsPerTick; ++guard) {
    start_next_activity(model, state, agent);
    if (self.program.empty()) return;
    const PendingAction pending = self.program.front();
    const Action& action = action_of(model, state, pending);
    if (action.kind == Kind::run_routine) {
      self.program.pop_front();
      if (action.repeat) self.program.push_front(pending);  // it comes round again after the task's actions
      const auto& actions = model.routines[action.target].actions;
      // A compound task given to a group: every member runs it, its gotos in formation.
      for (std::size_t i = actions.size(); i-- > 0;) {
        self.program.push_front({action.target, static_cast<int>(i), pending.step, pending.role, pending.group_size, pending.group});
      }
      continue;
    }
    if (!self.action_started) {
      if (!group_ready(state, agent, pending)) return;
      if (leaves_seat(action, self) && !clear_of_seat(state, agent)) return;
      if (!start_action(model, state, agent, action, pending)) return;
      self.action_started = true;
    }
    if (action.kind == Kind::join_queue && !self.queueing.served) tend_queueing(model, state, agent);
    if (action.kind == Kind::pick_up || action.kind == Kind::put_down) {
      tend_reaching(model, state, agent, action);
      if (self.carrying.phase == ReachPhase::none) {
        self.action_started = false;
        return;
      }
    }
    if (!action_done(state, agent, action, pending)) return;
    finish_action(state, agent);
    if (action.kind == Kind::leave) {
      leave_scene(model, state, agent, events::Left{});
      return;
    }
  }
}

}  // namespace

const Action& action_of(const scenario::Model& model, const State& state, const PendingAction& pending) {
  if (pending.routine == kCommandedAction) return state.commanded[pending.index];
  if (pending.routine == kActivityAction) return state.agents[pending.index].living.activity_action;
  return pending.routine >= 0 ? model.routines[pending.routine].actions[pending.index] : model.steps[pending.step].actions[pending.index];
}

void release_reservations(State& state, int agent) {
  AgentState& self = state.agents[agent];
  leave_queue(state, agent);
  self.reservation.location = {};
  self.reservation.space = {};
  self.reservation.slot = {};
}

void leave_scene(const scenario::Model& model, State& state, int agent, EventData event) {
  AgentState& self = state.agents[agent];
  self.active = false;
  self.left = true;
  self.program.clear();
  self.action_started = false;
  self.navigation.under_way = false;
  self.velocity = Vec2::Zero();
  release_reservations(state, agent);
  for (auto& members : state.groups) std::erase(members, agent);
  emit(model, state, model.agents[agent].id, std::move(event));
}

void let_people_in(const scenario::Model& model, State& state) {
  for (std::size_t a = 0; a < state.agents.size(); ++a) {
    AgentState& self = state.agents[a];
    if (self.active || self.left || model.agents[a].enters_at <= 0.0 || time_of(model, state) < model.agents[a].enters_at) continue;
    self.active = true;
    emit(model, state, model.agents[a].id, events::Entered{});
  }
}

void start_step(const scenario::Model& model, State& state, int step) {
  state.current_step = step;
  state.steps[step].started_tick = state.tick;
  const scenario::Step& definition = model.steps[step];
  emit(model, state, definition.name, events::StepStarted{step});
  for (std::size_t i = 0; i < definition.actions.size(); ++i) {
    const Action& action = definition.actions[i];
    if (action.group < 0) {
      state.agents[action.agent].program.push_back({-1, static_cast<int>(i), step});
      continue;
    }
    const std::vector<int>& members = state.groups[action.group];
    if (members.empty()) emit(model, state, model.groups[action.group].name, events::GroupEmpty{definition.name});
    for (std::size_t role = 0; role < members.size(); ++role) {
      state.agents[members[role]].program.push_back({-1, static_cast<int>(i), step, static_cast<int>(role), static_cast<int>(members.size()), action.group});
    }
  }
}

void make_request(const scenario::Model& model, State& state, int robot, int routine) {
  const Vec2 position = state.agents[robot].position;
  const std::int64_t id = state.next_request_id++;
  emit(model, state, model.agents[robot].id, events::Request{id, model.routines[routine].name, position.x(), position.y()});
  if (std::find(model.async_routines.begin(), model.async_routines.end(), routine) == model.async_routines.end()) {
    emit(model, state, model.agents[robot].id, events::RequestDropped{id, model.routines[routine].name, events::DropReason::no_response});
    return;
  }
  state.requests.push_back({id, robot, routine, position, state.tick, state.tick});
}

void update_requests(const scenario::Model& model, State& state) {
  const auto retry = ticks(model, kRequestRetryPeriod);
  const auto timeout = ticks(model, kRequestTimeout);
  std::vector<OpenRequest> still_open;
  for (OpenRequest& open : state.requests) {
    if (state.tick < open.next_try_tick) {
      still_open.push_back(open);
      continue;
    }
    int chosen = -1;
    double chosen_distance = kRequestRadius;
    for (std::size_t h = 0; h < state.agents.size(); ++h) {
      const double distance = (state.agents[h].position - open.position).norm();
      if (idle(model, state, static_cast<int>(h)) && distance <= chosen_distance && (chosen < 0 || distance < chosen_distance)) {
        chosen = static_cast<int>(h);
        chosen_distance = distance;
      }
    }
    const std::string& routine = model.routines[open.routine].name;
    if (chosen >= 0) {
      AgentState& human = state.agents[chosen];
      human.answering_request = true;
      for (std::size_t i = 0; i < model.routines[open.routine].actions.size(); ++i) human.program.push_back({open.routine, static_cast<int>(i), -1});
      emit(model, state, model.agents[chosen].id, events::RequestAccepted{open.id, routine, model.agents[open.robot].id, chosen_distance});
    } else if (state.tick - open.asked_tick + retry > timeout) {
      emit(model, state, model.agents[open.robot].id, events::RequestDropped{open.id, routine, events::DropReason::no_idle_human});
    } else {
      open.next_try_tick += retry;
      still_open.push_back(open);
    }
  }
  state.requests = std::move(still_open);
}

/// A robot still driving to its own controller's goal: the scenario waits for it, so a navigation
/// episode ends when the robot arrives (or at the time limit), not when the people are done.
bool robot_on_its_way(const State& state) {
  if (anyone_searching(state)) return true;
  return std::any_of(state.robots.begin(), state.robots.end(), [&state](const RobotRuntime& runtime) {
    const AgentState& self = state.agents[runtime.agent];
    return runtime.controller.goal && self.active && self.navigation.under_way && self.navigation.goal == runtime.controller.goal->position();
  });
}

void update_choreography(const scenario::Model& model, State& state) {
  // A finished step hands over to the next within the same tick, so its actions start without delay.
  for (std::size_t guard = 0; guard <= model.steps.size(); ++guard) {
    for (std::size_t a = 0; a < state.agents.size(); ++a) advance_agent(model, state, static_cast<int>(a));
    const int step = state.current_step;
    if (step >= static_cast<int>(model.steps.size())) {
      // A benchmark task's episode ends by the task or its length.
      if (!state.finished && !model.task && !robot_on_its_way(state) && !anyone_lives_on(model)) {
        state.finished = true;
        state.termination = Termination::scenario_end;
        emit(model, state, model.name, events::ScenarioFinished{});
      }
      return;
    }
    for (const AgentState& agent : state.agents) {
      for (const PendingAction& pending : agent.program) {
        if (pending.step == step) return;
      }
    }
    state.steps[step].finished_tick = state.tick;
    emit(model, state, model.steps[step].name, events::StepFinished{step, static_cast<double>(state.tick - state.steps[step].started_tick) * model.dt});
    if (step + 1 < static_cast<int>(model.steps.size())) {
      start_step(model, state, step + 1);
    } else {
      state.current_step = step + 1;
    }
  }
}

void interrupt(State& state, int human, std::span<const Action> actions) {
  AgentState& self = state.agents[human];
  for (auto action = actions.rbegin(); action != actions.rend(); ++action) {
    state.commanded.push_back(*action);
    self.program.push_front({kCommandedAction, static_cast<int>(state.commanded.size()) - 1, -1});
  }
  self.action_started = false;
  self.navigation.under_way = false;
  self.navigation.path.clear();
}

void startle(const scenario::Model& model, State& state, int human, int robot) {
  AgentState& self = state.agents[human];
  if (!self.active || model.agents[human].kind != AgentKind::human) return;
  if (self.reaction.startled_tick >= 0 && state.tick - self.reaction.startled_tick < ticks(model, kStartleRefractory)) return;
  self.reaction.startled_tick = state.tick;
  const Vec2 robot_at = state.agents[robot].position;
  const auto reaction = [&](Kind kind, const char* what) {
    Action action;
    action.agent = human;
    action.kind = kind;
    action.pointer = std::string("reaction: ") + what;
    return action;
  };
  std::vector<Action> actions;
  const bool may_step_back = !self.rooted && !self.reservation.space.valid();  // no room to in a cabin or a queue
  const Vec2 from_robot = self.position - robot_at;
  const Vec2 away = from_robot.norm() > 1e-9 ? Vec2(from_robot.normalized()) : Vec2(-core::heading_vector(self.heading));
  for (const double back : {kStartleStepBack, 0.5 * kStartleStepBack}) {
    const Vec2 to = self.position + back * away;
    if (!may_step_back || !model.grid.in_bounds(model.grid.cell_of(to)) || model.field.distance(model.grid, to) < model.agents[human].radius) continue;
    Action step_back = reaction(Kind::go_to_pose, "step back");
    step_back.pose = {to.x(), to.y(), core::direction_to(to, robot_at)};
    step_back.radius = scenario::kDefaultGoalRadius;
    actions.push_back(step_back);
    break;
  }
  const bool stepped_back = !actions.empty();
  Action look = reaction(Kind::look_at_agent, "look at the robot");
  look.target = robot;
  actions.push_back(look);
  Action pause = reaction(Kind::wait_duration, "look at the robot");
  pause.value = kStartleLook;
  actions.push_back(pause);
  interrupt(state, human, actions);
  emit(model, state, model.agents[human].id, events::Startled{model.agents[robot].id, stepped_back});
}

}  // namespace hrisim::sim
