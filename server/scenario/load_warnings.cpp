#include "scenario/load_warnings.hpp"

#include <functional>
#include <set>
#include <sstream>
#include <utility>

#include "core/json_schema.hpp"
#include "scenario/load.hpp"

namespace hrisim::scenario::loading {

void warn_about_social_force_goals(const Model& model, Errors& warnings) {
  auto social_force = [&](int agent) {
    return agent >= 0 && model.agents[agent].kind == AgentKind::human &&
           model.agents[agent].avoidance == humans::LocalAvoidance::social_force;
  };
  bool any = false;
  double radius = 0.0;
  for (std::size_t a = 0; a < model.agents.size(); ++a) {
    if (!social_force(static_cast<int>(a))) continue;
    any = true;
    radius = std::max(radius, model.agents[a].radius);
  }
  if (!any) return;
  const double standoff = social_force_standoff(model.social_force, radius, kPreferredSpeedMean);
  std::set<std::string> reported;
  auto check = [&](const Vec2& p, double goal_radius, const std::string& pointer, const std::string& what) {
    const double clearance = model.field.distance(model.grid, p);
    if (clearance + goal_radius >= standoff || !reported.insert(pointer).second) return;
    std::ostringstream message;
    message.precision(2);
    message << std::fixed << what << " is " << clearance << " m from an obstacle (goal radius " << goal_radius
            << " m); a social-force human may stop about " << standoff
            << " m away (use ORCA for it, or a smaller locomotion.social_force.obstacle_sigma)";
    warnings.push_back({pointer, message.str()});
  };
  std::function<void(const Action&, std::set<int>&)> visit = [&](const Action& action, std::set<int>& seen) {
    if (action.kind == Action::Kind::run_routine && action.target >= 0 && seen.insert(action.target).second) {
      for (const Action& inner : model.routines[action.target].actions) visit(inner, seen);
    } else if (action.kind == Action::Kind::go_to_location && action.target >= 0 && action.pose == Pose2{}) {
      const Location& location = model.locations[action.target];
      check(location.pose.position(), location.radius, "/locations/" + core::pointer_token(location.name),
            "location '" + location.name + "'");
    } else if (action.kind == Action::Kind::go_to_social_space && action.target >= 0) {
      const SocialSpace& space = model.social_spaces[action.target];
      for (std::size_t i = 0; i < space.slots.size(); ++i) {
        check(space.slots[i].position(), kDefaultGoalRadius,
              "/social_spaces/" + core::pointer_token(space.name) + "/slots/" + std::to_string(i),
              "slot " + std::to_string(i) + " of '" + space.name + "'");
      }
    } else if (action.kind == Action::Kind::go_to_pose) {
      check(action.pose.position(), action.radius, action.pointer + "/goto/pose", "goal pose");
    }
  };
  for (const Step& step : model.steps) {
    for (const Action& action : step.actions) {
      bool by_social_force = social_force(action.agent);
      if (action.group >= 0) {
        for (int member : model.groups[action.group].members) by_social_force |= social_force(member);
      }
      std::set<int> seen;
      if (by_social_force) visit(action, seen);
    }
  }
  for (int task : model.async_routines) {  // any idle human may answer, social-force ones included
    std::set<int> seen{task};
    for (const Action& action : model.routines[task].actions) visit(action, seen);
  }
}

void warn_about_unpublished_waits(const Model& model, Errors& warnings) {
  std::set<std::pair<std::string, std::string>> sent;
  std::set<std::string> topics;
  const auto send = [&](const std::string& topic, const std::string& message) {
    sent.insert({topic, message});
    topics.insert(topic);
  };
  const auto publishes = [&](const Action& action) {
    if (action.kind == Action::Kind::publish) send(action.topic, action.message);
  };
  for (const Routine& routine : model.routines) std::for_each(routine.actions.begin(), routine.actions.end(), publishes);
  for (const Step& step : model.steps) std::for_each(step.actions.begin(), step.actions.end(), publishes);
  for (const Elevator& elevator : model.elevators) {
    for (const int door : elevator.doors) {
      if (door < 0 || door >= static_cast<int>(model.doors.size())) continue;  // an unknown door, an error already
      for (const char* phase : {"closed", "opening", "open", "closing"}) send(elevator.topic + "/" + model.doors[door].name + "_state", phase);
    }
  }
  const auto check = [&](const Action& action) {
    if (action.kind != Action::Kind::wait_message || sent.contains({action.topic, action.message})) return;
    warnings.push_back({action.pointer + "/wait",
                        topics.contains(action.topic)
                            ? "waits for '" + action.message + "' on topic '" + action.topic + "', which is published there but never with that message: it waits until the time limit"
                            : "waits for a message on topic '" + action.topic + "' that nothing in the scenario publishes (no publish action, no elevator door): it waits until the time limit"});
  };
  for (const Routine& routine : model.routines) std::for_each(routine.actions.begin(), routine.actions.end(), check);
  for (const Step& step : model.steps) std::for_each(step.actions.begin(), step.actions.end(), check);
}

}  // namespace hrisim::scenario::loading
