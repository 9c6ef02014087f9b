#include "scenario/read_actions.hpp"

#include <algorithm>

#include "core/text.hpp"
#include "humans/motion.hpp"
#include "scenario/reaching.hpp"

namespace hrisim::scenario::loading {
namespace {

/// What a group (a pair too) can be given: the whole group walks a goto in formation; every member
/// does the others, and performs a routine's actions likewise, its gotos in formation.
constexpr const char* kGroupActions[] = {"goto", "routine", "wait", "look_at", "turn", "motion", "say"};

}  // namespace

ActionReader::ActionReader(Context& context, const Model& model) : context_(context), model_(model) {}

Action ActionReader::read(const json& entry, const std::string& pointer, bool in_routine) {
  Action action;
  action.pointer = pointer;
  if (entry.contains("agent") && entry.contains("group")) {
    context_.error(pointer, "an action names an agent or a group, not both");
  } else if (entry.contains("agent") || entry.contains("group")) {
    const char* key = entry.contains("agent") ? "agent" : "group";
    if (in_routine) {
      context_.error(pointer + "/" + key, "actions of a routine do not name an agent or group: whoever performs the routine acts");
    } else if (entry.contains("agent")) {
      action.agent = context_.resolve(context_.names.agents, entry["agent"], pointer + "/agent", "agent");
    } else if (!std::any_of(std::begin(kGroupActions), std::end(kGroupActions), [&](const char* kind) { return entry.contains(kind); })) {
      context_.error(pointer + "/group", "a group can be given goto, routine, wait, look_at, turn, motion or say");
    } else {
      action.group = context_.resolve(context_.names.groups, entry["group"], pointer + "/group", "group");
    }
  } else if (!in_routine) {
    context_.error(pointer, "missing required key 'agent' (or 'group')");
  }
  auto robot = [&](const json& name, const std::string& at) {
    const int agent = context_.resolve(context_.names.agents, name, at, "agent");
    if (agent >= 0 && !context_.names.robots.contains(name.get<std::string>())) {
      context_.error(at, "'" + name.get<std::string>() + "' is not a robot");
    }
    return agent;
  };
  if (entry.contains("goto")) {
    const json& go = entry["goto"];
    if (go.contains("location")) {
      action.kind = Action::Kind::go_to_location;
      action.target = context_.resolve(context_.names.locations, go["location"], pointer + "/goto/location", "location");
      if (go.contains("offset")) action.pose = read_pose(go["offset"]);
    } else if (go.contains("social_space")) {
      action.kind = Action::Kind::go_to_social_space;
      action.target = context_.resolve(context_.names.social_spaces, go["social_space"], pointer + "/goto/social_space", "social space");
    } else {
      action.kind = Action::Kind::go_to_pose;
      action.pose = read_pose(go["pose"]);
      action.radius = go.value("radius", kDefaultGoalRadius);
      context_.check_free(model_, action.pose.position(), pointer + "/goto/pose", "goal pose");
    }
  } else if (entry.contains("wait")) {
    const json& wait = entry["wait"];
    if (wait.contains("duration")) {
      action.kind = Action::Kind::wait_duration;
      action.value = wait["duration"];
    } else {
      action.kind = Action::Kind::wait_message;
      action.topic = wait["topic"];
      action.message = wait["message"];
    }
  } else if (entry.contains("look_at")) {
    const json& look = entry["look_at"];
    if (look.contains("angle")) {
      action.kind = Action::Kind::look_at_angle;
      action.value = look["angle"];
    } else if (look.contains("agent")) {
      action.kind = Action::Kind::look_at_agent;
      action.target = context_.resolve(context_.names.agents, look["agent"], pointer + "/look_at/agent", "agent");
    } else if (look.contains("object")) {
      read_look_at_object(look["object"], pointer + "/look_at/object", action);
    } else {
      action.kind = Action::Kind::look_at_location;
      action.target = context_.resolve(context_.names.locations, look["location"], pointer + "/look_at/location", "location");
    }
  } else if (entry.contains("turn")) {
    action.kind = entry["turn"].contains("by") ? Action::Kind::turn_by : Action::Kind::turn_to;
    action.value = entry["turn"].contains("by") ? entry["turn"]["by"] : entry["turn"]["to"];
  } else if (entry.contains("publish")) {
    action.kind = Action::Kind::publish;
    action.topic = entry["publish"]["topic"];
    action.message = entry["publish"]["message"];
  } else if (entry.contains("form_group")) {
    action.kind = Action::Kind::form_group;
    action.target = context_.names.groups.at(entry["form_group"]["group"]);
    action.members = context_.members_of(entry["form_group"]["members"], pointer + "/form_group/members");
  } else if (entry.contains("dismantle_group")) {
    action.kind = Action::Kind::dismantle_group;
    action.target = context_.resolve(context_.names.groups, entry["dismantle_group"], pointer + "/dismantle_group", "group");
  } else if (entry.contains("harass") || entry.contains("stop_and_look")) {
    const bool harass = entry.contains("harass");
    const json& attitude = entry[harass ? "harass" : "stop_and_look"];
    action.kind = harass ? Action::Kind::harass : Action::Kind::stop_and_look;
    action.target = robot(attitude["robot"], pointer + (harass ? "/harass/robot" : "/stop_and_look/robot"));
    action.value = attitude["duration"];
    action.radius = attitude.value("distance", harass ? kHarassDistance : kStopAndLookDistance);
  } else if (entry.contains("request")) {
    action.kind = Action::Kind::request;
    action.target = context_.resolve(context_.names.routines, entry["request"]["routine"], pointer + "/request/routine", "routine");
    if (action.agent >= 0 && !context_.names.robots.contains(model_.agents[action.agent].id)) {
      context_.error(pointer + "/agent", "only a robot makes requests");
    }
  } else if (entry.contains("motion")) {
    action.kind = Action::Kind::play_motion;
    action.motion = entry["motion"]["name"];
    const humans::MotionClip* clip = humans::builtin_motion(action.motion);
    if (!clip) {
      context_.error(pointer + "/motion/name", "no motion primitive '" + action.motion + "' (" + core::join(humans::builtin_motion_names()) + ")");
    } else {
      action.value = entry["motion"].value("duration", clip->duration());
    }
    require_human(action, "plays motions");
  } else if (entry.contains("say")) {
    read_say(entry["say"], pointer + "/say", action);
  } else if (entry.contains("sit_on")) {
    read_sit_on(entry["sit_on"], pointer + "/sit_on", action);
  } else if (entry.contains("pick_up")) {
    read_pick_up(entry["pick_up"], pointer + "/pick_up", action);
  } else if (entry.contains("put_down")) {
    read_put_down(entry["put_down"], pointer + "/put_down", action);
  } else if (entry.contains("leave")) {
    action.kind = Action::Kind::leave;
    require_human(action, "leave the scene");
  } else if (entry.contains("queue")) {
    action.kind = Action::Kind::join_queue;
    action.target = context_.resolve(context_.names.queues, entry["queue"], pointer + "/queue", "queue");
    require_human(action, "queues");
  } else {
    action.kind = Action::Kind::run_routine;
    action.target = context_.resolve(context_.names.routines, entry["routine"], pointer + "/routine", "routine");
    action.repeat = entry.value("repeat", false);
  }
  if (action.agent >= 0) {
    const AgentDef& agent = model_.agents[action.agent];
    using K = Action::Kind;
    const bool moves = action.kind == K::go_to_location || action.kind == K::go_to_social_space || action.kind == K::go_to_pose ||
                       action.kind == K::look_at_angle || action.kind == K::look_at_agent || action.kind == K::look_at_location || action.kind == K::look_at_object ||
                       action.kind == K::turn_by || action.kind == K::turn_to;
    if (moves && agent.robot_model && !agent.robot_model->drive) {
      context_.error(pointer + "/agent", "robot '" + agent.id + "' (model " + agent.robot_model->name + ") has no drive: it cannot move or turn");
    }
  }
  return action;
}

void ActionReader::read_look_at_object(const json& name, const std::string& pointer, Action& action) {
  const std::optional<Action> look = model_.look_at_object(name.get<std::string>());
  if (!look) {
    context_.error(pointer, "no movable object or obstacle named '" + name.get<std::string>() + "'");
    return;
  }
  action.kind = look->kind;
  action.target = look->target;
  action.pose = look->pose;
}

/// Speech for `duration` s, or a clip for its own length (the scenario's `clips`).
void ActionReader::read_say(const json& say, const std::string& pointer, Action& action) {
  action.kind = Action::Kind::say;
  if (say.contains("clip")) {
    const std::string name = say["clip"];
    const std::optional<Action> clip = model_.say_clip(name);
    if (!clip) {
      std::string known;
      for (const auto& named : model_.clips) known += (known.empty() ? "" : ", ") + named.first;
      context_.error(pointer + "/clip", "unknown clip '" + name + "'" + (known.empty() ? " (none in 'clips')" : " (known: " + known + ")"));
      return;
    }
    action.target = clip->target;
    action.value = clip->value;
  } else {
    action.value = say["duration"];
  }
  if (action.agent >= 0 && model_.agents[action.agent].kind != AgentKind::human) context_.error(pointer, "only a human speaks");
}

/// The radius of the person acting, as far as the action tells (a routine's: the default).
double ActionReader::acting_radius(const Action& action) const {
  return action.agent >= 0 ? model_.agents[action.agent].radius : kDefaultAgentRadius;
}

void ActionReader::require_human(const Action& action, const char* what) {
  if (action.agent >= 0 && model_.agents[action.agent].kind != AgentKind::human) context_.error(action.pointer + "/agent", std::string("only a human ") + what);
}

/// An obstacle's anchor, or an error at `pointer` naming those it has.
std::optional<Pose2> ActionReader::anchor_of(const Obstacle& obstacle, const std::string& anchor, const std::string& pointer) {
  const auto found = obstacle.anchors.find(anchor);
  if (found != obstacle.anchors.end()) return found->second;
  std::string known;
  for (const auto& [name, unused] : obstacle.anchors) known += (known.empty() ? "" : ", ") + name;
  context_.error(pointer, "obstacle '" + obstacle.name + "' has no anchor '" + anchor + "'" + (known.empty() ? " (it has none)" : " (it has: " + known + ")"));
  return std::nullopt;
}

const Obstacle* ActionReader::obstacle_named(const std::string& name, const std::string& pointer) {
  for (const Obstacle& obstacle : model_.obstacles) {
    if (obstacle.name == name) return &obstacle;
  }
  context_.error(pointer, "no obstacle named '" + name + "'");
  return nullptr;
}

/// Sitting on an obstacle's anchor, whose front a person can reach.
void ActionReader::read_sit_on(const json& sit, const std::string& pointer, Action& action) {
  action.kind = Action::Kind::sit_on;
  require_human(action, "sits");
  const Obstacle* obstacle = obstacle_named(sit["obstacle"], pointer + "/obstacle");
  const std::string anchor = sit.value("anchor", kDefaultSeatAnchor);
  if (!obstacle || !anchor_of(*obstacle, anchor, pointer + (sit.contains("anchor") ? "/anchor" : "/obstacle"))) return;
  action.target = model_.find_seat(obstacle->name, anchor);
  const Seat& seat = model_.seats[action.target];
  if (!seat_approach(model_, seat, acting_radius(action))) {
    context_.error(pointer, "seat '" + seat.name + "' cannot be reached: its front (facing " + core::number_text(seat.pose.theta) +
                       " rad) is blocked within " + core::number_text(sit_down_travel() + kSeatApproachReach) + " m");
  }
}

void ActionReader::read_pick_up(const json& pick, const std::string& pointer, Action& action) {
  action.kind = Action::Kind::pick_up;
  require_human(action, "picks things up");
  const std::string name = pick["object"];
  for (std::size_t o = 0; o < model_.objects.size(); ++o) {
    if (model_.objects[o].name == name) action.target = static_cast<int>(o);
  }
  if (action.target < 0) {
    std::string known;
    for (const MovableObject& object : model_.objects) known += (known.empty() ? "" : ", ") + object.name;
    context_.error(pointer + "/object", "no movable object named '" + name + "'" + (known.empty() ? " (none in 'objects')" : " (known: " + known + ")"));
  }
}

/// Where a carried object goes: on an obstacle's top (an anchor or its centre) or on the floor.
void ActionReader::read_put_down(const json& put, const std::string& pointer, Action& action) {
  action.kind = Action::Kind::put_down;
  require_human(action, "puts things down");
  if (put.contains("at")) {
    if (put.contains("anchor")) context_.error(pointer + "/anchor", "an anchor belongs to an obstacle: give it with 'on'");
    const Vec2 at = read_point(put["at"]);
    action.pose = {at.x(), at.y(), 0.0};
    context_.check_free(model_, at, pointer + "/at", "put_down point");
  } else {
    const Obstacle* obstacle = obstacle_named(put["on"], pointer + "/on");
    if (!obstacle) return;
    action.value = obstacle->height;
    action.pose = obstacle->frame;
    if (put.contains("anchor")) {
      const std::optional<Pose2> anchor = anchor_of(*obstacle, put["anchor"], pointer + "/anchor");
      if (anchor) action.pose = *anchor;
    }
  }
  if (!reach_spot(model_, action.pose.position(), action.pose.position(), acting_radius(action))) {
    context_.error(pointer, "nobody can stand within " + core::number_text(kMaxHandReach) + " m of (" + core::point_text(action.pose.position()) + ") to put something there");
  }
}

}  // namespace hrisim::scenario::loading
