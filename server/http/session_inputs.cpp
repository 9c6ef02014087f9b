#include "http/session_inputs.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "core/json_schema.hpp"
#include "http/request_helpers.hpp"
#include "http/session_limits.hpp"
#include "http/session_views.hpp"
#include "scenario/human_commands.hpp"

namespace hrisim::http {

using nlohmann::json;

/// Checks one command (of the form api/openapi.yaml's Command, as the request contract checked it)
/// against the session and returns the input that gives it (nothing is changed yet).
static episode::Input checked_command(const sim::Session& session, const json& command, const std::string& at) {
  const bool human = command.contains("human");
  const std::string who = command[human ? "human" : "robot"];
  sim::AgentId id;
  try {
    id = session.agent_id(who);
  } catch (const core::Error&) {
    throw core::Error(core::ErrorCode::bad_request, "no agent '" + who + "'", {{"pointer", at + (human ? "/human" : "/robot")}});
  }
  const int agent = session.index_of(id);
  const auto& def = session.model().agents[agent];
  if (human) {
    const std::string text = command["command"];
    const scenario::Action action = scenario::parse_human_command(session.model(), agent, text);  // throws when it is wrong
    return episode::inputs::HumanCommand{agent, action, text};
  }
  if (def.kind != scenario::AgentKind::robot) throw core::Error(core::ErrorCode::bad_request, "'" + who + "' is not a robot", {{"pointer", at + "/robot"}});
  const sim::RobotRuntime* runtime = session.robot_runtime(id);
  if (command.contains("velocity")) {
    const json& velocity = command["velocity"];
    const double linear = velocity["linear"].get<double>(), angular = velocity["angular"].get<double>();
    if (!runtime || !def.robot_model->drive) {
      throw core::Error(core::ErrorCode::bad_request, "robot '" + who + "' has no drive to take a velocity", {{"pointer", at + "/velocity"}});
    }
    return episode::inputs::RobotTwist{agent, {linear, angular}};
  }
  if (command.contains("joints")) {
    const json& joints = command["joints"];
    if (!runtime) throw core::Error(core::ErrorCode::bad_request, "robot '" + who + "' has no joints", {{"pointer", at + "/joints"}});
    const std::string group = joints["group"];
    const auto found = def.robot_model->groups.find(group);
    if (found == def.robot_model->groups.end()) {
      throw core::Error(core::ErrorCode::bad_request, "robot model '" + def.robot_model->name + "' has no joint group '" + group + "'",
                        {{"pointer", at + "/joints/group"}});
    }
    const bool velocities = joints.contains("velocities");
    const json& values = joints[velocities ? "velocities" : "positions"];
    if (values.size() != found->second.size()) {
      throw core::Error(core::ErrorCode::bad_request,
                        std::string(velocities ? "velocities" : "positions") + ": " + std::to_string(found->second.size()) + " numbers for group '" + group + "'",
                        {{"pointer", at + "/joints/" + (velocities ? "velocities" : "positions")}});
    }
    const std::vector<double> targets = values.get<std::vector<double>>();
    return episode::inputs::RobotJoints{agent, group, targets, velocities};
  }
  if (command.contains("gripper")) {
    const json& gripper = command["gripper"];
    if (!runtime || !def.robot_model->gripper) {
      throw core::Error(core::ErrorCode::bad_request, "robot '" + who + "' has no gripper", {{"pointer", at + "/gripper"}});
    }
    const bool close = gripper == "close";
    return episode::inputs::RobotGripper{agent, close};
  }
  if (command.contains("request")) {
    const int routine = session.model().find_routine(command["request"]);
    if (routine < 0) throw core::Error(core::ErrorCode::bad_request, "request: no routine by that name", {{"pointer", at + "/request"}});
    return episode::inputs::RobotRequest{agent, routine};
  }
  throw core::Error(core::ErrorCode::bad_request, "a robot command gives velocity, joints, gripper or request", {{"pointer", at}});
}

std::optional<std::vector<double>> action_of(const json& action) {
  if (action.is_null()) return std::nullopt;
  return action.get<std::vector<double>>();
}

/// 409 for stepping a session the server steps itself.
void check_lockstep(const LiveSession& live) {
  if (live.mode != Mode::lockstep) {
    throw core::Error(core::ErrorCode::conflict, "session " + live.id + " runs in realtime mode: the server steps it", {{"mode", to_string(live.mode)}});
  }
}

/// Gives a list of commands, each checked before any is given (the session's lock held).
json give_commands(LiveSession& live, const json& commands) {
  const sim::Session& session = live.session();
  std::vector<episode::Input> apply;
  for (std::size_t i = 0; i < commands.size(); ++i) {
    const std::string at = "/commands/" + std::to_string(i);
    try {
      apply.push_back(checked_command(session, commands[i], at));
    } catch (const core::Error& e) {
      json details = e.details();
      const std::string inner = details.value("pointer", "");
      details["pointer"] = inner.starts_with(at) ? inner : at + inner;
      throw core::Error(core::ErrorCode::bad_request, at + ": " + e.what(), details);
    }
  }
  for (const auto& input : apply) live.episode->give(input);
  return {{"applied", apply.size()}, {"tick", session.state().tick}};
}

/// Advances up to `steps` environment steps (the session's lock held; each the task's frame skip in
/// ticks, one tick without a task): the status, the events of those steps, and Gymnasium's terminated
/// (the task's ending, or the scenario's last step done) and truncated (its time limit).
std::string step_session(LiveSession& live, std::int64_t steps, const std::optional<std::vector<double>>& action, std::string_view type) {
  const sim::Session& session = live.session();
  if (action && !live.environment()) throw core::Error(core::ErrorCode::conflict, "this session has no robot that can act", {{"pointer", "/action"}});
  const double reward = live.episode->step(action, steps);
  // Written directly, not built as a tree: learning code asks for thousands of these a second.
  core::JsonWriter out;
  out.begin_object();
  if (!type.empty()) out.key("type").value(type);
  write_status(out, live);
  // Gymnasium's step: observation, reward (summed over the steps), terminated, truncated, info.
  write_observation(out, live);
  out.key("reward").value(reward);
  // Each event is in exactly one step reply: those since the last reply, including what commands and
  // the session's start gave between steps. (Counted, not dated: a step stamps some events with the
  // tick it starts at.)
  out.key("events").begin_array();
  const auto& all = session.state().events;
  for (std::size_t e = live.events_reported; e < all.size(); ++e) out.value(event_json(all[e]));
  out.end_array();
  live.events_reported = all.size();
  const sim::Termination termination = session.state().termination;
  out.key("terminated").value(termination == sim::Termination::scenario_end || termination == sim::Termination::goal);
  out.key("truncated").value(termination == sim::Termination::timeout);
  out.end_object();
  return out.take();
}

Response step_many(Registry& registry, const Caller& caller, const json& body, std::string_view type) {
  const json& ids = body["sessions"];
  const bool with_actions = body.contains("actions");
  if (with_actions && body["actions"].size() != ids.size()) {
    throw core::Error(core::ErrorCode::bad_request, "actions: one action (a list of numbers, or null) per session", {{"pointer", "/actions"}});
  }
  const std::int64_t steps = body.value("n", std::int64_t{1});
  // Everything is checked before anything is stepped.
  std::vector<std::function<Response()>> parts;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const std::string at = "/sessions/" + std::to_string(i);
    const std::string& id = ids[i].get_ref<const std::string&>();
    std::shared_ptr<LiveSession> live;
    try {
      live = registry.find(id, caller);
      check_lockstep(*live);
    } catch (const core::Error& e) {
      nlohmann::json details = e.details();
      details["pointer"] = at;
      throw core::Error(e.code(), e.what(), std::move(details));
    }
    auto action = with_actions ? action_of(body["actions"][i]) : std::nullopt;
    parts.push_back([live = std::move(live), steps, action = std::move(action)] {
      std::lock_guard lock(live->mutex);
      return Response{200, "application/json", step_session(*live, steps, action), {}, {}};
    });
  }
  return Response::spread_over(std::move(parts), [type = std::string(type)](std::vector<Response> answers) {
    core::JsonWriter out;
    out.begin_object();
    if (!type.empty()) out.key("type").value(type);
    out.key("results").begin_array();
    for (const Response& answer : answers) out.raw(answer.body);  // a step reply, or {"error": …}
    out.end_array();
    out.end_object();
    return Response{200, "application/json", out.take(), {}, {}};
  });
}

/// Keeps the episode's present point as a snapshot (the session's lock held).
json take_snapshot(LiveSession& live) {
  if (live.snapshots.size() >= kMaxSnapshots) {
    throw core::Error(core::ErrorCode::conflict, "session " + live.id + " keeps its maximum of " + std::to_string(kMaxSnapshots) +
                                                     " snapshots: delete one (DELETE /api/v1/sessions/" + live.id + "/snapshots/{snapshot})");
  }
  const std::string id = "snap-" + std::to_string(++live.snapshots_taken);
  episode::Episode::Snapshot snapshot = live.episode->snapshot();
  json reply = snapshot_json(id, snapshot);
  live.snapshots.emplace(id, std::move(snapshot));
  return reply;
}

/// The snapshot a restore names, checked before the work (the session's lock held).
static const episode::Episode::Snapshot& snapshot_named(const LiveSession& live, const json& body) {
  const auto found = live.snapshots.find(body["snapshot"].get<std::string>());
  if (found == live.snapshots.end()) {
    throw core::Error(core::ErrorCode::not_found, "session " + live.id + " has no snapshot '" + body["snapshot"].get<std::string>() + "'",
                      {{"pointer", "/snapshot"}});
  }
  return found->second;
}

/// Goes back (or forth) to a snapshot: the episode again from its start with the snapshot's inputs, up
/// to its tick (the session's lock held). Gymnasium's observation and info, with the status.
/// The session goes on from `episode` (restored or rewound): viewers see a fresh start; the events up
/// to here are not reported again; a realtime session's clock starts from its tick.
json go_on_from(LiveSession& live, std::unique_ptr<episode::Episode> episode) {
  live.episode = std::move(episode);
  ++live.generation;
  live.events_reported = live.session().state().events.size();
  live.realtime_origin = Clock::now();
  live.realtime_origin_tick = live.session().state().tick;
  json reply = status_of(live);
  add_observation(live, reply);
  return reply;
}

json reset_session(LiveSession& live, const json& seed_given, const json& poses) {
  const std::int64_t seed = seed_given.is_null() ? live.seed : seed_given.get<std::int64_t>();
  // A fresh episode of the same scenario: everything starts again from tick 0, then the poses given
  // are set (all or none: a bad one leaves the old session as it was).
  std::unique_ptr<episode::Episode> fresh = live.new_episode(live.session().shared_model(), seed);
  for (const auto& [name, pose] : poses.items()) fresh->give(place(fresh->session(), name, pose, "/options/poses/" + core::pointer_token(name)));
  live.seed = seed;
  ++live.generation;
  live.episode = std::move(fresh);
  live.snapshots.clear();
  live.events_reported = 0;
  live.realtime_origin = Clock::now();
  live.realtime_origin_tick = 0;
  json reply = status_of(live);
  add_observation(live, reply);
  return reply;
}

json restore_snapshot(LiveSession& live, const json& body) { return go_on_from(live, live.episode->restore(snapshot_named(live, body))); }

json seek_session(LiveSession& live, const json& body) {
  const std::int64_t now = live.session().state().tick;
  const bool lockstep = live.mode == Mode::lockstep;
  const std::int64_t tick = body["tick"], furthest = lockstep ? now + kMaxStepsPerRequest : now;
  if (tick > furthest) {
    throw core::Error(core::ErrorCode::bad_request,
                      "tick: at most " + std::to_string(furthest) + (lockstep ? " (the present tick and one step request's maximum)" : " (the present tick)"),
                      {{"pointer", "/tick"}});
  }
  if (tick <= now) {
    json reply = go_on_from(live, live.episode->rewind(tick));
    reply["resimulated_ticks"] = live.episode->ticks_simulated_again();
    return reply;
  }
  // Forward: the ticks a clock would give, no new inputs.
  while (live.session().state().tick < tick && !live.episode->over()) live.episode->tick();
  json reply = status_of(live);
  add_observation(live, reply);
  reply["resimulated_ticks"] = 0;
  return reply;
}

/// The input that places an agent or object by name at a pose {x, y, z, roll, pitch, yaw} (checked; `at`
/// is its JSON pointer prefix): seed 000's uniform pose interface. People and robots stay upright on
/// the floor; a place off the floor is refused when the input is given.
episode::Input place(const sim::Session& session, const std::string& name, const json& body, const std::string& at) {
  const double x = body["x"].get<double>(), y = body["y"].get<double>();
  const auto optional = [&](const char* key) { return body.value(key, 0.0); };
  const double z = optional("z"), roll = optional("roll"), pitch = optional("pitch"), yaw = optional("yaw");
  if (session.model().find_agent(name) >= 0) {
    for (const char* key : {"z", "roll", "pitch"}) {
      if (optional(key) != 0.0) {
        throw core::Error(core::ErrorCode::bad_request, std::string(key) + ": agents stand upright on the floor", {{"pointer", at + "/" + key}});
      }
    }
    const int agent = session.index_of(session.agent_id(name));
    return episode::inputs::PlaceAgent{agent, {x, y, yaw}};
  }
  const auto& objects = session.model().objects;
  const auto found = std::find_if(objects.begin(), objects.end(), [&](const scenario::MovableObject& o) { return o.name == name; });
  if (found == objects.end()) throw core::Error(core::ErrorCode::not_found, "no agent or object '" + name + "'", {{"name", name}, {"pointer", at}});
  const int object = static_cast<int>(found - objects.begin());
  return episode::inputs::PlaceObject{object, {x, y, z, roll, pitch, yaw}};
}

}  // namespace hrisim::http

namespace hrisim::http {

namespace {

/// An input as the API takes it: {"command": a command object} or {"place": name, "pose": {…}}.
struct InputJson {
  const scenario::Model& model;
  json operator()(const episode::inputs::HumanCommand& given) const {
    return {{"command", {{"human", model.agents[given.human].id}, {"command", given.text}}}};
  }
  json operator()(const episode::inputs::RobotTwist& given) const {
    return {{"command", {{"robot", model.agents[given.robot].id}, {"velocity", {{"linear", given.twist.linear}, {"angular", given.twist.angular}}}}}};
  }
  json operator()(const episode::inputs::RobotJoints& given) const {
    return {{"command",
             {{"robot", model.agents[given.robot].id}, {"joints", {{"group", given.group}, {given.velocities ? "velocities" : "positions", given.targets}}}}}};
  }
  json operator()(const episode::inputs::RobotGripper& given) const {
    return {{"command", {{"robot", model.agents[given.robot].id}, {"gripper", given.close ? "close" : "open"}}}};
  }
  json operator()(const episode::inputs::RobotRequest& given) const {
    return {{"command", {{"robot", model.agents[given.robot].id}, {"request", model.routines[given.routine].name}}}};
  }
  json operator()(const episode::inputs::PlaceAgent& given) const {
    return {{"place", model.agents[given.agent].id}, {"pose", {{"x", given.pose.x}, {"y", given.pose.y}, {"yaw", given.pose.theta}}}};
  }
  json operator()(const episode::inputs::PlaceObject& given) const {
    const core::Pose3& pose = given.pose;
    return {{"place", model.objects[given.object].name},
            {"pose", {{"x", pose.x}, {"y", pose.y}, {"z", pose.z}, {"roll", pose.roll}, {"pitch", pose.pitch}, {"yaw", pose.yaw}}}};
  }
};

}  // namespace

json input_json(const scenario::Model& model, const episode::Input& input) { return std::visit(InputJson{model}, input); }

episode::Input input_of(const sim::Session& session, const json& given, const std::string& at) {
  if (given.contains("command")) return checked_command(session, given["command"], at + "/command");
  if (given.contains("place")) {
    try {
      return place(session, given["place"], given["pose"], at + "/pose");
    } catch (const core::Error& e) {
      if (e.code() != core::ErrorCode::not_found) throw;
      throw core::Error(core::ErrorCode::bad_request, e.what(), {{"pointer", at + "/place"}});
    }
  }
  throw core::Error(core::ErrorCode::bad_request, "an input is {\"command\": …} or {\"place\": name, \"pose\": …}", {{"pointer", at}});
}

}  // namespace hrisim::http
