#include "sim/activities.hpp"

#include <algorithm>
#include <cmath>

#include "sim/events.hpp"

namespace hrisim::sim {
namespace {

using scenario::Activity;
using Kind = scenario::Action::Kind;

/// The next activity after `current`, drawn from its row.
int draw_next(const std::vector<double>& row, core::Random& random) {
  const double u = random.uniform();
  double cumulative = 0.0;
  int last = 0;
  for (std::size_t next = 0; next < row.size(); ++next) {
    if (row[next] <= 0.0) continue;
    cumulative += row[next];
    last = static_cast<int>(next);
    if (u < cumulative) return last;
  }
  return last;  // a row adding up to a hair under 1
}

scenario::Action action_for(const scenario::ActivityModel& model, const Activity& activity, const State& state, int agent, core::Random& random) {
  scenario::Action action;
  action.agent = agent;
  action.pointer = "/activity_models/" + model.name + "/activities/" + activity.name;
  const double duration = random.uniform(activity.min_duration, activity.max_duration);
  switch (activity.kind) {
    case Activity::Kind::motion:
      action.kind = Kind::play_motion;
      action.motion = activity.motion;
      action.value = duration;
      break;
    case Activity::Kind::walk: {
      // A place holds one person: the walk draws among those nobody else holds, or waits a moment.
      std::vector<int> free;
      for (const int location : activity.locations) {
        const bool held = std::any_of(state.agents.begin(), state.agents.end(), [&](const AgentState& other) {
          return &other != &state.agents[agent] && other.reservation.location.value == location;
        });
        if (!held) free.push_back(location);
      }
      const double u = random.uniform();
      if (free.empty()) {
        action.kind = Kind::wait_duration;
        action.value = kPlacesTakenWait;
        break;
      }
      action.kind = Kind::go_to_location;
      action.target = free[std::min(static_cast<std::size_t>(u * static_cast<double>(free.size())), free.size() - 1)];
      break;
    }
    case Activity::Kind::wait:
      action.kind = Kind::wait_duration;
      action.value = duration;
      break;
    case Activity::Kind::turn:
      action.kind = Kind::turn_by;
      action.value = random.uniform(activity.min_angle, activity.max_angle);
      break;
  }
  return action;
}

void begin_activity(const scenario::Model& model, State& state, int agent, const scenario::ActivityModel& living) {
  const scenario::AgentDef& def = model.agents[agent];
  AgentState& self = state.agents[agent];
  self.living.activity = ActivityIndex(!self.living.activity.valid() ? living.start : draw_next(living.transitions_for(def.type)[self.living.activity.value], self.living.activity_random));
  const Activity& activity = living.activities[self.living.activity.value];
  self.living.activity_action = action_for(living, activity, state, agent, self.living.activity_random);
  self.program.push_back({kActivityAction, agent, -1});
  events::ActivityStarted started{activity.name, living.name, std::nullopt, std::nullopt};
  if (self.living.activity_action.kind == Kind::go_to_location) started.location = model.locations[self.living.activity_action.target].name;
  if (activity.kind == Activity::Kind::walk && self.living.activity_action.kind == Kind::wait_duration) started.waiting = "every place is taken";
  emit(model, state, def.id, std::move(started));
}

/// Gives the person one action of their own (the activity's slot in the program).
void push_own_action(State& state, int agent, scenario::Action action) {
  action.agent = agent;
  state.agents[agent].living.activity_action = std::move(action);
  state.agents[agent].program.push_back({kActivityAction, agent, -1});
}

/// The clock's reading, in seconds since midnight of its first day, at the current tick.
double clock_seconds(const scenario::Model& model, const State& state) {
  return state.clock_start + model.clock->speed * static_cast<double>(state.tick) * model.dt;
}

/// A stay whose time is up ends a pause or a walk under way at once; a motion plays to its end.
void end_stay_if_due(State& state, int agent) {
  AgentState& self = state.agents[agent];
  if (!self.living.room.valid() || state.tick < self.living.stay_until_tick || self.program.empty()) return;
  const PendingAction& front = self.program.front();
  if (front.routine != kActivityAction || self.living.activity_action.kind == Kind::play_motion) return;
  if (self.living.activity_action.kind == Kind::go_to_location) {
    self.navigation.under_way = false;
    self.navigation.path.clear();
    self.living.in_room = false;
  }
  self.program.pop_front();
  self.action_started = false;
}

/// Draws the next stay's room from the hour's row of presence probabilities and its length.
void begin_stay(const scenario::Model& model, State& state, int agent, const scenario::DailySchedule& schedule) {
  AgentState& self = state.agents[agent];
  const double now = clock_seconds(model, state);
  const int hour = static_cast<int>(scenario::time_of_day(session_clock(model, state), static_cast<double>(state.tick) * model.dt) / scenario::kSecondsPerHour);
  const int room = draw_next(schedule.presence[static_cast<std::size_t>(hour)], self.living.activity_random);
  const double hour_ends = (std::floor(now / scenario::kSecondsPerHour) + 1.0) * scenario::kSecondsPerHour;
  const double ends = std::min(now + self.living.activity_random.uniform(schedule.min_stay, schedule.max_stay), hour_ends);
  self.living.stay_until_tick = state.tick + std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil((ends - now) / (model.clock->speed * model.dt))));
  if (room != self.living.room.value) {
    self.living.room = RoomIndex(room);
    self.living.in_room = false;
    self.living.activity = {};
  }
  emit(model, state, model.agents[agent].id,
       events::StayStarted{model.rooms[room].name, scenario::format_time_of_day(std::fmod(now, scenario::kSecondsPerDay)),
                           scenario::format_time_of_day(std::fmod(ends, scenario::kSecondsPerDay))});
}

/// Sets off to a free spot of the stay's room, standing up first if need be.
void set_off(const scenario::Model& model, State& state, int agent) {
  AgentState& self = state.agents[agent];
  scenario::Action action;
  const scenario::Posture posture = posture_of(self);
  if (posture != scenario::Posture::standing) {
    action.kind = Kind::play_motion;
    action.motion = posture == scenario::Posture::seated ? "stand_up" : "get_up";
    action.value = humans::builtin_motion(action.motion)->duration();
    action.pointer = "daily schedule: stand up before leaving";
    push_own_action(state, agent, std::move(action));
    return;
  }
  const scenario::Room& room = model.rooms[self.living.room.value];
  for (const int spot : room.spots) {
    const bool held = std::any_of(state.agents.begin(), state.agents.end(), [&](const AgentState& other) {
      return &other != &self && other.reservation.location.value == spot;
    });
    if (held) continue;
    action.kind = Kind::go_to_location;
    action.target = spot;
    action.pointer = "daily schedule: to " + room.name;
    self.living.in_room = true;
    push_own_action(state, agent, std::move(action));
    return;
  }
  action.kind = Kind::wait_duration;  // every spot taken: try again in a moment
  action.value = kPlacesTakenWait;
  action.pointer = "daily schedule: every spot in " + room.name + " is taken";
  push_own_action(state, agent, std::move(action));
}

void follow_schedule(const scenario::Model& model, State& state, int agent) {
  const scenario::DailySchedule& schedule = model.daily_schedules[model.agents[agent].daily_schedule];
  AgentState& self = state.agents[agent];
  end_stay_if_due(state, agent);
  if (!self.program.empty()) return;
  if (!self.living.room.valid() || state.tick >= self.living.stay_until_tick) begin_stay(model, state, agent, schedule);
  if (!self.living.in_room) {
    set_off(model, state, agent);
    return;
  }
  const int living = schedule.activities[static_cast<std::size_t>(self.living.room.value)];
  if (living >= 0) {
    begin_activity(model, state, agent, model.activity_models[living]);
    return;
  }
  scenario::Action stand;  // a room without a model: stand there until the stay is over
  stand.kind = Kind::wait_duration;
  stand.value = static_cast<double>(self.living.stay_until_tick - state.tick) * model.dt;
  stand.pointer = "daily schedule: in " + model.rooms[self.living.room.value].name;
  push_own_action(state, agent, std::move(stand));
}

}  // namespace

scenario::Posture posture_of(const AgentState& self) {
  if (!self.animation.motion || self.animation.motion_released_tick >= 0) return scenario::Posture::standing;
  return scenario::posture_at(*self.animation.motion, self.animation.motion->duration());
}

scenario::Clock session_clock(const scenario::Model& model, const State& state) {
  scenario::Clock clock = *model.clock;
  clock.start = clock.latest_start = state.clock_start;
  return clock;
}

bool anyone_lives_on(const scenario::Model& model) {
  return std::any_of(model.agents.begin(), model.agents.end(),
                     [](const scenario::AgentDef& def) { return def.activity_model >= 0 || def.daily_schedule >= 0; });
}

const scenario::ActivityModel* activity_model_of(const scenario::Model& model, const State& state, int agent) {
  const scenario::AgentDef& def = model.agents[agent];
  if (def.activity_model >= 0) return &model.activity_models[def.activity_model];
  const AgentState& self = state.agents[agent];
  if (def.daily_schedule < 0 || !self.living.room.valid()) return nullptr;
  const int living = model.daily_schedules[def.daily_schedule].activities[static_cast<std::size_t>(self.living.room.value)];
  return living >= 0 ? &model.activity_models[living] : nullptr;
}

void start_next_activity(const scenario::Model& model, State& state, int agent) {
  const scenario::AgentDef& def = model.agents[agent];
  AgentState& self = state.agents[agent];
  if (!self.active || state.current_step < static_cast<int>(model.steps.size())) return;
  if (def.daily_schedule >= 0) {
    follow_schedule(model, state, agent);
  } else if (def.activity_model >= 0 && self.program.empty()) {
    begin_activity(model, state, agent, model.activity_models[def.activity_model]);
  }
}

}  // namespace hrisim::sim
