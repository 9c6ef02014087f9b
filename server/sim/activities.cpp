#include "sim/activities.hpp"

#include <algorithm>

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
          return &other != &state.agents[agent] && other.reserved_location == location;
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
  }
  return action;
}

}  // namespace

bool anyone_lives_on(const scenario::Model& model) {
  return std::any_of(model.agents.begin(), model.agents.end(), [](const scenario::AgentDef& def) { return def.activity_model >= 0; });
}

void start_next_activity(const scenario::Model& model, State& state, int agent) {
  const scenario::AgentDef& def = model.agents[agent];
  AgentState& self = state.agents[agent];
  if (def.activity_model < 0 || !self.active || !self.program.empty() || state.current_step < static_cast<int>(model.steps.size())) return;
  const scenario::ActivityModel& living = model.activity_models[def.activity_model];
  self.activity = self.activity < 0 ? living.start : draw_next(living.transitions_for(def.type)[self.activity], self.activity_random);
  const Activity& activity = living.activities[self.activity];
  self.activity_action = action_for(living, activity, state, agent, self.activity_random);
  self.program.push_back({kActivityAction, agent, -1});
  nlohmann::json data{{"activity", activity.name}, {"model", living.name}};
  if (self.activity_action.kind == Kind::go_to_location) data["location"] = model.locations[self.activity_action.target].name;
  if (activity.kind == Activity::Kind::walk && self.activity_action.kind == Kind::wait_duration) data["waiting"] = "every place is taken";
  emit(model, state, "activity_started", def.id, std::move(data));
}

}  // namespace hrisim::sim
