#include "sim/search.hpp"

#include <algorithm>
#include <limits>
#include <numbers>

#include "sim/activities.hpp"
#include "sim/events.hpp"
#include "sim/walking.hpp"

namespace hrisim::sim {
namespace {

using Strategy = scenario::RobotController::SearchStrategy;

/// The planned distance from the robot to a room's lookout (infinite without a way).
double way_to(const scenario::Model& model, const State& state, const RobotRuntime& runtime, int room) {
  const Vec2 from = state.agents[runtime.agent].position;
  const Vec2 to = model.locations[model.rooms[room].lookout].pose.position();
  const auto path = model.planner.plan(from, to, model.agents[runtime.agent].radius);
  if (!path) return std::numeric_limits<double>::infinity();
  double length = 0.0;
  Vec2 at = from;
  for (const Vec2& waypoint : *path) {
    length += (waypoint - at).norm();
    at = waypoint;
  }
  return length;
}

/// The room to look into next: not yet looked into, the most likely first (presence) or the nearest.
int next_room(const scenario::Model& model, const State& state, const RobotRuntime& runtime) {
  const scenario::RobotController& controller = runtime.controller;
  std::vector<double> likelihood(model.rooms.size(), 0.0);
  if (controller.search_strategy == Strategy::presence) {
    const scenario::DailySchedule& schedule = model.daily_schedules[model.agents[controller.search_person].daily_schedule];
    const double time = static_cast<double>(state.tick) * model.dt;
    const int hour = static_cast<int>(scenario::time_of_day(session_clock(model, state), time) / scenario::kSecondsPerHour);
    likelihood = schedule.presence[static_cast<std::size_t>(hour)];
  }
  int best = -1;
  double best_likelihood = -1.0, best_way = 0.0;
  for (std::size_t room = 0; room < model.rooms.size(); ++room) {
    if (runtime.search.looked_into[room]) continue;
    const double way = way_to(model, state, runtime, static_cast<int>(room));
    if (likelihood[room] > best_likelihood || (likelihood[room] == best_likelihood && way < best_way)) {
      best = static_cast<int>(room);
      best_likelihood = likelihood[room];
      best_way = way;
    }
  }
  return best;
}

}  // namespace

std::optional<robots::Twist> search_command(const scenario::Model& model, State& state, RobotRuntime& runtime) {
  RobotRuntime::Search& search = runtime.search;
  AgentState& self = state.agents[runtime.agent];
  if (search.found) return robots::Twist{};
  search.looked_into.resize(model.rooms.size(), 0);
  if (search.scanning) {
    search.turned += std::abs(core::wrap_angle(self.heading - search.last_heading));
    search.last_heading = self.heading;
    if (search.turned < 2.0 * std::numbers::pi) return robots::Twist{0.0, kSearchScanRate};
    search.scanning = false;
    search.looked_into[static_cast<std::size_t>(search.room)] = 1;
    search.room = -1;
  }
  if (search.room >= 0 && self.navigation.under_way) {
    const double distance = (model.locations[model.rooms[search.room].lookout].pose.position() - self.position).norm();
    if (distance < search.closest - kSearchProgress) {
      search.closest = distance;
      search.closer_tick = state.tick;
    } else if (static_cast<double>(state.tick - search.closer_tick) * model.dt > kSearchPatience) {
      self.navigation.under_way = false;  // no nearer: look around from here
      self.navigation.path.clear();
    }
  }
  if (search.room >= 0 && !self.navigation.under_way) {  // at the lookout (or no way there): look around
    search.scanning = true;
    search.turned = 0.0;
    search.last_heading = self.heading;
    return robots::Twist{0.0, kSearchScanRate};
  }
  if (search.room >= 0) return std::nullopt;
  if (std::all_of(search.looked_into.begin(), search.looked_into.end(), [](std::uint8_t done) { return done != 0; })) {
    std::fill(search.looked_into.begin(), search.looked_into.end(), 0);  // start over: the person may have moved
  }
  search.room = next_room(model, state, runtime);
  const scenario::Location& lookout = model.locations[model.rooms[search.room].lookout];
  go_to(model, state, runtime.agent, lookout.pose, kLookoutRadius, false);
  search.closest = (lookout.pose.position() - self.position).norm();
  search.closer_tick = state.tick;
  emit(model, state, model.agents[runtime.agent].id, events::SearchRoom{model.rooms[search.room].name});
  return std::nullopt;
}

void notice_people_found(const scenario::Model& model, State& state) {
  for (RobotRuntime& runtime : state.robots) {
    if (runtime.controller.kind != scenario::RobotController::Kind::search || runtime.search.found || runtime.people.tick != state.tick) continue;
    const int person = runtime.controller.search_person;
    const auto seen = std::find_if(runtime.people.people.begin(), runtime.people.people.end(),
                                   [person](const sensors::Detection& detection) { return detection.agent == person && detection.face_visible; });
    if (seen == runtime.people.people.end()) continue;
    runtime.search.found = true;
    state.agents[runtime.agent].navigation.under_way = false;
    const AgentState& found = state.agents[person];
    emit(model, state, model.agents[runtime.agent].id,
         events::PersonFound{model.agents[person].id, found.living.room.valid() ? std::optional(model.rooms[found.living.room.value].name) : std::nullopt, seen->range});
    if (!state.finished) {
      state.finished = true;
      state.termination = Termination::goal;
    }
  }
}

bool anyone_searching(const State& state) {
  return std::any_of(state.robots.begin(), state.robots.end(), [&state](const RobotRuntime& runtime) {
    return runtime.controller.kind == scenario::RobotController::Kind::search && !runtime.search.found && state.agents[runtime.agent].active;
  });
}

}  // namespace hrisim::sim
