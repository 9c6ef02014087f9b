#include "scenario/human_commands.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "core/text.hpp"
#include "humans/motion.hpp"

namespace hrisim::scenario {

using Kind = Action::Kind;

Action parse_human_command(const Model& model, int agent, std::string_view text) {
  if (model.agents.at(agent).kind != AgentKind::human) throw core::Error(core::ErrorCode::bad_request, "'" + model.agents[agent].id + "' is not a human");
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
    if (!model.grid.in_bounds(model.grid.cell_of(goal)) || model.grid.blocked(goal)) {
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
    if (const int other = model.find_agent(name); other >= 0) {
      action.kind = Kind::look_at_agent;
      action.target = other;
    } else {
      const auto location = std::find_if(model.locations.begin(), model.locations.end(),
                                         [&](const scenario::Location& l) { return l.name == name; });
      if (location != model.locations.end()) {
        action.kind = Kind::look_at_location;
        action.target = static_cast<int>(location - model.locations.begin());
      } else if (const std::optional<Action> object = model.look_at_object(name)) {
        action.kind = object->kind;
        action.target = object->target;
        action.pose = object->pose;
      } else {
        throw core::Error(core::ErrorCode::bad_request, "look_at: no agent, location, object or obstacle named '" + name + "'");
      }
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
  } else if (verb == "say") {
    action.kind = Kind::say;
    std::string what;
    if (!(in >> what)) throw core::Error(core::ErrorCode::bad_request, "say: for how many seconds, or which clip?");
    if (const std::optional<Action> clip = model.say_clip(what)) {
      action.target = clip->target;
      action.value = clip->value;
    } else {
      char* end = nullptr;
      action.value = std::strtod(what.c_str(), &end);
      if (end != what.c_str() + what.size() || !std::isfinite(action.value) || action.value <= 0.0) {
        throw core::Error(core::ErrorCode::bad_request, "say: '" + what + "' is neither seconds > 0 nor one of the scenario's clips");
      }
    }
  } else if (verb == "behaviour") {
    std::string name;
    in >> name;
    const std::optional<humans::BehaviourType> type = humans::behaviour_type(name);
    if (!type) throw core::Error(core::ErrorCode::bad_request, "behaviour: which? (regular, impassive, surprised, scared, curious, threatening)");
    action.kind = Kind::set_behaviour;
    action.target = static_cast<int>(*type);
  } else {
    throw core::Error(core::ErrorCode::bad_request,
                      "unknown command '" + verb + "' (walk X Y, wait S, turn_to RAD, look_at NAME, motion NAME [S], say S|CLIP, behaviour NAME)");
  }
  std::string extra;
  if (in >> extra) throw core::Error(core::ErrorCode::bad_request, verb + ": unexpected '" + extra + "'");
  return action;
}

}  // namespace hrisim::scenario
