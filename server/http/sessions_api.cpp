#include "http/sessions_api.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <thread>

#include "core/error.hpp"
#include "core/json_schema.hpp"
#include "core/random.hpp"
#include "episode/episode.hpp"
#include "http/frames.hpp"
#include "http/request_helpers.hpp"
#include "metrics/episode_metrics.hpp"
#include "render/image_codec.hpp"
#include "runs/spec.hpp"
#include "sim/scene_view.hpp"
#include "sim/session.hpp"

namespace hrisim::http {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

/// A live session records at most this many bodies (people and robot, summed over its steps) for its
/// metrics on demand: about 150 MB by the size of a body's record (not measured), 1.5 hours of the
/// elevator's six people at 60 Hz, half a minute of a thousand. Its metrics then cover the steps up
/// to `recorded_until_tick`.
constexpr std::size_t kMaxLiveRecordedBodies = 2'000'000;

struct Live {
  std::string id, scenario;
  std::string owner;  ///< who created it (the token's name); empty without owners
  std::int64_t seed = 0;
  std::string mode = "lockstep";  ///< lockstep: clients step it; realtime: the server does, by the wall clock
  double realtime_factor = 1.0;   ///< realtime: simulated seconds per wall-clock second
  std::optional<json> controller;  ///< replaced the robot under test's, when given
  std::mutex mutex;  ///< one request at a time works on the session
  std::unique_ptr<episode::Episode> episode;
  core::MemoryBudget* recording_memory = nullptr;  ///< shared by every recording of the server
  std::size_t events_reported = 0;  ///< events before this index were in a step reply already
  std::uint64_t generation = 0;     ///< counts resets and restores, so that viewers notice a fresh start
  std::map<std::string, episode::Episode::Snapshot> snapshots;  ///< of this episode (a reset drops them)
  std::uint64_t snapshots_taken = 0;
  Clock::time_point last_used;
  /// WebSockets open on it; shared with them, as they hold no reference to the session.
  std::shared_ptr<std::atomic<int>> clients = std::make_shared<std::atomic<int>>(0);
  // Realtime: the wall-clock time and tick it was last (re)started from.
  Clock::time_point realtime_origin;
  std::int64_t realtime_origin_tick = 0;

  sim::Session& session() { return episode->session(); }
  const sim::Session& session() const { return episode->session(); }
  /// The Gymnasium environment; null without a robot that can act.
  const tasks::Environment* environment() const { return episode->environment(); }

  /// A fresh episode of the same model (the lock held, or before anyone else has it).
  void start(std::shared_ptr<const scenario::Model> model) {
    episode = std::make_unique<episode::Episode>(
        std::move(model), static_cast<std::uint64_t>(seed),
        episode::Settings{std::nullopt, {}, true, sim::RecorderLimits{kMaxLiveRecordedBodies, recording_memory}});
    events_reported = 0;
    realtime_origin = Clock::now();
    realtime_origin_tick = 0;
  }
};

/// Realtime sessions are stepped this often (wall clock), s.
constexpr double kRealtimeTick = 1.0 / 60.0;
/// A realtime session that falls behind catches up at most this much simulated time per tick (or two
/// ticks' worth at its factor, when more), s.
constexpr double kRealtimeMaxCatchUp = 0.5;
/// Largest realtime factor accepted.
constexpr double kMaxRealtimeFactor = 100.0;
/// Snapshots one session keeps at most.
constexpr std::size_t kMaxSnapshots = 32;

json event_json(const sim::Event& event) {
  return {{"tick", event.tick}, {"time", event.time}, {"kind", event.kind}, {"subject", event.subject}, {"data", event.data}};
}

/// The events of tick `first` and later; they are kept in tick order, so only the new ones are looked at.
json events_since(const sim::Session& session, std::int64_t first) {
  const auto& events = session.state().events;
  auto begin = events.end();
  while (begin != events.begin() && std::prev(begin)->tick >= first) --begin;
  json list = json::array();
  for (auto event = begin; event != events.end(); ++event) list.push_back(event_json(*event));
  return list;
}

/// Status of a session (its lock held).
json status_of(const Live& live) {
  const sim::Session& session = live.session();
  const sim::State& state = session.state();
  const bool in_step = state.step < static_cast<int>(session.model().steps.size());
  return {{"id", live.id},
          {"scenario", live.scenario},
          {"seed", live.seed},
          {"mode", live.mode},
          {"realtime_factor", live.mode == "realtime" ? json(live.realtime_factor) : json()},
          {"controller", live.controller ? *live.controller : json()},
          {"connected_clients", live.clients->load()},
          {"tick", state.tick},
          {"time", session.time()},
          {"dt", session.model().dt},
          {"status", state.finished ? "finished" : "running"},
          {"termination", state.finished ? json(state.termination) : json()},
          {"step", in_step ? json{{"index", state.step}, {"name", session.model().steps[state.step].name}} : json()},
          {"task", session.model().task && live.environment() ? json{{"name", session.model().task->name},
                                                                     {"step_ticks", live.environment()->step_ticks()},
                                                                     {"terminated", live.environment()->terminated()}}
                                                              : json()},
          {"state_hash", session.state_hash_hex()}};
}

/// Every agent's pose and motion, requests waiting for an answer, and the events since a tick.
/// The waypoints an agent still has to pass, from where it is: [[x, y], …]; empty when it stands.
json path_ahead(const sim::AgentState& agent) {
  json points = json::array();
  if (!agent.navigating) return points;
  points.push_back({agent.position.x(), agent.position.y()});
  for (std::size_t w = agent.path_index; w < agent.path.size(); ++w) points.push_back({agent.path[w].x(), agent.path[w].y()});
  return points;
}

json state_of(const Live& live, std::int64_t events_since_tick) {
  const sim::Session& session = live.session();
  const sim::State& state = session.state();
  json agents = json::array();
  for (std::size_t i = 0; i < state.agents.size(); ++i) {
    const sim::AgentState& agent = state.agents[i];
    const scenario::AgentDef& def = session.model().agents[i];
    agents.push_back({{"id", def.id},
                      {"kind", def.kind == scenario::AgentKind::human ? "human" : "robot"},
                      {"active", agent.active},
                      {"x", agent.position.x()},
                      {"y", agent.position.y()},
                      {"theta", agent.heading},
                      {"vx", agent.velocity.x()},
                      {"vy", agent.velocity.y()},
                      {"busy", !agent.program.empty()},
                      {"path", path_ahead(agent)},
                      {"motion", agent.motion ? json(agent.motion->name()) : json()}});
  }
  json requests = json::array();
  for (const sim::OpenRequest& open : state.requests) {
    requests.push_back({{"robot", session.model().agents[open.robot].id}, {"task", session.model().tasks[open.task].name}});
  }
  json reply = status_of(live);
  reply["agents"] = agents;
  reply["requests"] = requests;
  reply["events"] = events_since(session, events_since_tick);
  return reply;
}

/// A number field of a command; 400 naming it otherwise.
double number_of(const json& object, const char* key, const std::string& at) {
  if (!object.is_object() || !object.contains(key) || !object[key].is_number() || !std::isfinite(object[key].get<double>())) {
    throw core::Error(core::ErrorCode::bad_request, std::string(key) + " must be a number", {{"pointer", at + "/" + key}});
  }
  return object[key].get<double>();
}

/// Checks one command against the session and returns the input that gives it (nothing is changed yet).
episode::Episode::Input checked_command(const sim::Session& session, const json& command, const std::string& at) {
  if (!command.is_object()) throw core::Error(core::ErrorCode::bad_request, "a command is an object", {{"pointer", at}});
  const bool human = command.contains("human"), robot = command.contains("robot");
  if (human == robot || !command[human ? "human" : "robot"].is_string()) {
    throw core::Error(core::ErrorCode::bad_request, "a command names a \"human\" or a \"robot\"", {{"pointer", at}});
  }
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
    refuse_unknown_keys(command, {"human", "command"});
    if (!command.contains("command") || !command["command"].is_string()) {
      throw core::Error(core::ErrorCode::bad_request, "command: the text of a command is required", {{"pointer", at + "/command"}});
    }
    const std::string text = command["command"];
    const scenario::Action action = session.parse_human_command(id, text);  // throws when it is wrong
    return [action, text](sim::Session& to) { to.command_human(action, text); };
  }
  refuse_unknown_keys(command, {"robot", "velocity", "joints", "gripper", "request"});
  if (def.kind != scenario::AgentKind::robot) throw core::Error(core::ErrorCode::bad_request, "'" + who + "' is not a robot", {{"pointer", at + "/robot"}});
  const sim::RobotRuntime* runtime = session.robot_runtime(id);
  if (command.contains("velocity")) {
    const json& velocity = command["velocity"];
    const double linear = number_of(velocity, "linear", at + "/velocity"), angular = number_of(velocity, "angular", at + "/velocity");
    if (!runtime || !def.robot_model->drive) {
      throw core::Error(core::ErrorCode::bad_request, "robot '" + who + "' has no drive to take a velocity", {{"pointer", at + "/velocity"}});
    }
    return [agent, linear, angular](sim::Session& to) { to.command_robot_twist(to.agent_at(agent), {linear, angular}); };
  }
  if (command.contains("joints")) {
    const json& joints = command["joints"];
    if (!runtime) throw core::Error(core::ErrorCode::bad_request, "robot '" + who + "' has no joints", {{"pointer", at + "/joints"}});
    if (!joints.is_object() || !joints.contains("group") || !joints["group"].is_string()) {
      throw core::Error(core::ErrorCode::bad_request, "joints: a group name is required", {{"pointer", at + "/joints/group"}});
    }
    const std::string group = joints["group"];
    const auto found = def.robot_model->groups.find(group);
    if (found == def.robot_model->groups.end()) {
      throw core::Error(core::ErrorCode::bad_request, "robot model '" + def.robot_model->name + "' has no joint group '" + group + "'",
                        {{"pointer", at + "/joints/group"}});
    }
    const bool velocities = joints.contains("velocities");
    const json& values = joints[velocities ? "velocities" : "positions"];
    if (!values.is_array() || values.size() != found->second.size() ||
        !std::all_of(values.begin(), values.end(), [](const json& v) { return v.is_number() && std::isfinite(v.get<double>()); })) {
      throw core::Error(core::ErrorCode::bad_request,
                        std::string(velocities ? "velocities" : "positions") + ": " + std::to_string(found->second.size()) + " numbers for group '" + group + "'",
                        {{"pointer", at + "/joints/" + (velocities ? "velocities" : "positions")}});
    }
    const std::vector<double> targets = values.get<std::vector<double>>();
    return [agent, group, targets, velocities](sim::Session& to) { to.command_robot_joints(to.agent_at(agent), group, targets, velocities); };
  }
  if (command.contains("gripper")) {
    const json& gripper = command["gripper"];
    if (!gripper.is_string() || (gripper != "open" && gripper != "close")) {
      throw core::Error(core::ErrorCode::bad_request, "gripper: \"open\" or \"close\"", {{"pointer", at + "/gripper"}});
    }
    if (!runtime || !def.robot_model->gripper) {
      throw core::Error(core::ErrorCode::bad_request, "robot '" + who + "' has no gripper", {{"pointer", at + "/gripper"}});
    }
    const bool close = gripper == "close";
    return [agent, close](sim::Session& to) { to.command_robot_gripper(to.agent_at(agent), close); };
  }
  if (command.contains("request")) {
    const int task = command["request"].is_string() ? session.model().find_task(command["request"]) : -1;
    if (task < 0) throw core::Error(core::ErrorCode::bad_request, "request: no task by that name", {{"pointer", at + "/request"}});
    return [agent, task](sim::Session& to) { to.request(to.agent_at(agent), task); };
  }
  throw core::Error(core::ErrorCode::bad_request, "a robot command gives velocity, joints, gripper or request", {{"pointer", at}});
}

/// A pose as x, y, z, roll, pitch, yaw (rpy about fixed x, y, z).
json pose_json(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d r = pose.rotation();  // = Rz(yaw) Ry(pitch) Rx(roll)
  const double yaw = std::atan2(r(1, 0), r(0, 0)), pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0)), roll = std::atan2(r(2, 1), r(2, 2));
  return {{"x", pose.translation().x()}, {"y", pose.translation().y()}, {"z", pose.translation().z()},
          {"roll", roll}, {"pitch", pitch}, {"yaw", yaw}};
}

/// A number as JSON, infinities spelled "inf" and "-inf", which JSON numbers cannot hold (REP 117's
/// out-of-range laser values, unbounded Box spaces).
json number_or_infinity(double value) {
  if (std::isfinite(value)) return value;
  return value > 0 ? "inf" : "-inf";
}

/// A Gymnasium space in gym-http-api's form: {"name": "Box", shape, low, high, dtype} or {"name": "Discrete", n}.
/// low and high hold one value per element, or one for all of them. An image observation names its
/// camera: the observation is that camera's frame, not in the step's JSON.
json space_json(const tasks::Space& space, const std::optional<tasks::ImageObservation>& image = std::nullopt) {
  if (space.name == "Discrete") return {{"name", "Discrete"}, {"n", space.n}};
  json low = json::array(), high = json::array();
  for (const double value : space.low) low.push_back(number_or_infinity(value));
  for (const double value : space.high) high.push_back(number_or_infinity(value));
  json doc = {{"name", space.name}, {"shape", space.shape}, {"low", low}, {"high", high}, {"dtype", space.dtype}};
  if (image) doc["camera"] = {{"name", image->camera}, {"width", image->width}, {"height", image->height}};
  return doc;
}

/// The optional "action" of a step: a list of numbers.
std::optional<std::vector<double>> action_of(const json& body) {
  if (!body.contains("action")) return std::nullopt;
  const json& action = body["action"];
  if (!action.is_array()) throw core::Error(core::ErrorCode::bad_request, "action: a list of numbers", {{"pointer", "/action"}});
  std::vector<double> values;
  for (std::size_t i = 0; i < action.size(); ++i) {
    if (!action[i].is_number()) throw core::Error(core::ErrorCode::bad_request, "action: a list of numbers", {{"pointer", "/action/" + std::to_string(i)}});
    values.push_back(action[i].get<double>());
  }
  return values;
}

/// 409 for stepping a session the server steps itself.
void check_lockstep(const Live& live) {
  if (live.mode != "lockstep") {
    throw core::Error(core::ErrorCode::conflict, "session " + live.id + " runs in realtime mode: the server steps it", {{"mode", live.mode}});
  }
}

/// A robot's latest sensor readings and its joints (the session's lock held).
json sensors_of(const sim::Session& session, const std::string& name) {
  const int agent = session.model().find_agent(name);
  if (agent < 0) throw core::Error(core::ErrorCode::not_found, "no agent '" + name + "'", {{"name", name}});
  const sim::RobotRuntime* runtime = session.robot_runtime(session.agent_id(name));
  if (!runtime) throw core::Error(core::ErrorCode::not_found, "'" + name + "' is not a robot with a model", {{"name", name}});
  json lasers = json::array();
  for (const auto& sensor : runtime->lasers) {
    const sim::LaserReading& reading = sensor.reading;
    json ranges = json::array();
    for (const double range : reading.ranges) ranges.push_back(number_or_infinity(range));
    lasers.push_back({{"sensor", reading.sensor}, {"type", sensor.mount->type}, {"tick", reading.tick},
                      {"pose", {{"x", reading.pose.x}, {"y", reading.pose.y}, {"theta", reading.pose.theta}}}, {"height", reading.height},
                      {"angle_min", reading.angle_min}, {"angle_increment", reading.angle_increment}, {"range_min", reading.range_min},
                      {"range_max", reading.range_max}, {"ranges", ranges}});
  }
  json people = json::array();
  for (const sensors::Detection& person : runtime->people.people) {
    people.push_back({{"id", session.model().agents[person.agent].id}, {"x", person.position.x()}, {"y", person.position.y()},
                      {"vx", person.velocity.x()}, {"vy", person.velocity.y()}, {"range", person.range}, {"bearing", person.bearing}});
  }
  json joints = json::array();
  const auto& description = runtime->robot.description();
  for (std::size_t j = 0; j < description.joints.size(); ++j) {
    if (description.joints[j].type == robots::JointType::fixed) continue;
    joints.push_back({{"name", description.joints[j].name}, {"position", runtime->robot.joint_position(static_cast<int>(j))},
                      {"velocity", runtime->robot.joint_velocity(static_cast<int>(j))}});
  }
  json contacts = json::array();
  for (const sim::Contact& contact : runtime->contacts) {
    const std::string with = contact.agent >= 0    ? session.model().agents[contact.agent].id
                             : contact.object >= 0 ? session.model().objects[contact.object].name
                                                   : "map";
    contacts.push_back({{"with", with}, {"part", contact.part}});
  }
  const sim::OdometryReading& odometry = runtime->odometry_reading;
  return {{"robot", name},
          {"tick", session.state().tick},
          {"lasers", lasers},
          {"people", {{"tick", runtime->people.tick}, {"detections", people}}},
          {"odometry", {{"tick", odometry.tick}, {"x", odometry.pose.x}, {"y", odometry.pose.y}, {"theta", odometry.pose.theta},
                        {"linear", odometry.twist.linear}, {"angular", odometry.twist.angular}}},
          {"joints", joints},
          {"gripper_closed", runtime->robot.gripper_closed()},
          {"contacts", contacts}};
}

/// Every agent's and movable object's pose.
json poses_of(const sim::Session& session) {
  json agents = json::array(), objects = json::array();
  for (std::size_t i = 0; i < session.state().agents.size(); ++i) {
    const sim::AgentState& agent = session.state().agents[i];
    agents.push_back({{"id", session.model().agents[i].id}, {"x", agent.position.x()}, {"y", agent.position.y()}, {"z", 0.0},
                      {"roll", 0.0}, {"pitch", 0.0}, {"yaw", agent.heading}});
  }
  for (std::size_t o = 0; o < session.model().objects.size(); ++o) {
    json pose = pose_json(session.object_pose(static_cast<int>(o)));
    pose["name"] = session.model().objects[o].name;
    objects.push_back(pose);
  }
  return {{"agents", agents}, {"objects", objects}};
}

/// Gives a list of commands, each checked before any is given (the session's lock held).
json give_commands(Live& live, const json& commands) {
  const sim::Session& session = live.session();
  std::vector<episode::Episode::Input> apply;
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

/// Gymnasium's observation and info now: the observation null when it is a camera image (fetched as
/// a binary camera frame), info the tick, time and the last step's reward terms.
void add_observation(const Live& live, json& reply) {
  const sim::Session& session = live.session();
  reply["observation"] = live.environment() && !live.environment()->image() ? json(live.environment()->observe(session)) : json();
  reply["info"] = {{"tick", session.state().tick}, {"time", session.time()}};
  if (live.environment()) reply["info"].update(live.environment()->info());
}

/// Advances up to `steps` environment steps (the session's lock held; each the task's frame skip in
/// ticks, one tick without a task): the status, the events of those steps, and Gymnasium's terminated
/// (the task's ending, or the scenario's last step done) and truncated (its time limit).
json step_session(Live& live, std::int64_t steps, const std::optional<std::vector<double>>& action = std::nullopt) {
  const sim::Session& session = live.session();
  if (action && !live.environment()) throw core::Error(core::ErrorCode::conflict, "this session has no robot that can act", {{"pointer", "/action"}});
  const double reward = live.episode->step(action, steps);
  json reply = status_of(live);
  // Gymnasium's step: observation, reward (summed over the steps), terminated, truncated, info.
  add_observation(live, reply);
  reply["reward"] = reward;
  // Each event is in exactly one step reply: those since the last reply, including what commands and
  // the session's start gave between steps. (Counted, not dated: a step stamps some events with the
  // tick it starts at.)
  json events = json::array();
  const auto& all = session.state().events;
  for (std::size_t e = live.events_reported; e < all.size(); ++e) events.push_back(event_json(all[e]));
  live.events_reported = all.size();
  reply["events"] = events;
  reply["terminated"] = session.state().termination == "scenario_end" || session.state().termination == "goal";
  reply["truncated"] = session.state().termination == "timeout";
  return reply;
}

json snapshot_json(const std::string& id, const episode::Episode::Snapshot& snapshot) {
  return {{"snapshot", id}, {"tick", snapshot.tick}, {"state_hash", sim::hash_hex(snapshot.state_hash)}};
}

/// Keeps the episode's present point as a snapshot (the session's lock held).
json take_snapshot(Live& live) {
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
const episode::Episode::Snapshot& snapshot_named(const Live& live, const json& body) {
  refuse_unknown_keys(body, {"snapshot"});
  if (!body.contains("snapshot") || !body["snapshot"].is_string()) {
    throw core::Error(core::ErrorCode::bad_request, "snapshot: the id of a snapshot of this session is required", {{"pointer", "/snapshot"}});
  }
  const auto found = live.snapshots.find(body["snapshot"].get<std::string>());
  if (found == live.snapshots.end()) {
    throw core::Error(core::ErrorCode::not_found, "session " + live.id + " has no snapshot '" + body["snapshot"].get<std::string>() + "'",
                      {{"pointer", "/snapshot"}});
  }
  return found->second;
}

/// Goes back (or forth) to a snapshot: the episode again from its start with the snapshot's inputs, up
/// to its tick (the session's lock held). Gymnasium's observation and info, with the status.
json restore_snapshot(Live& live, const json& body) {
  live.episode = live.episode->restore(snapshot_named(live, body));
  ++live.generation;
  live.events_reported = live.session().state().events.size();
  live.realtime_origin = Clock::now();
  live.realtime_origin_tick = live.session().state().tick;
  json reply = status_of(live);
  add_observation(live, reply);
  return reply;
}

/// Answers with the session's lock held: at once when it is free, else on the worker pool, so that an
/// I/O thread never waits behind a long step (health checks and other sessions stay answered).
Response locked(std::shared_ptr<Live> live, std::function<Response(Live&)> work) {
  if (std::unique_lock lock(live->mutex, std::try_to_lock); lock) return work(*live);
  return Response::later([live = std::move(live), work = std::move(work)] {
    std::lock_guard lock(live->mutex);
    return work(*live);
  });
}

class Registry {
 public:
  explicit Registry(SessionLimits limits) : limits_(limits), ticker_([this](std::stop_token stop) { step_realtime(stop); }) {}
  ~Registry() {
    ticker_.request_stop();
    ticker_.join();
  }

  std::shared_ptr<Live> create(const std::string& scenario, std::shared_ptr<const scenario::Model> model, std::int64_t seed,
                               const std::string& mode, double realtime_factor, std::optional<json> controller, const std::string& owner) {
    std::lock_guard lock(mutex_);
    expire_idle();
    if (static_cast<int>(sessions_.size()) >= limits_.max_sessions) {
      throw core::Error(core::ErrorCode::unavailable,
                        "the server holds its maximum of " + std::to_string(limits_.max_sessions) + " sessions: delete one or retry later",
                        {{"max_sessions", limits_.max_sessions}, {"retry_after", kSessionRetryAfter}});
    }
    auto live = std::make_shared<Live>();
    live->id = core::unguessable_id('s');
    live->scenario = scenario;
    live->seed = seed;
    live->mode = mode;
    live->realtime_factor = realtime_factor;
    live->controller = std::move(controller);
    live->owner = owner;
    live->recording_memory = limits_.recording_memory;
    live->start(std::move(model));
    live->last_used = Clock::now();
    sessions_.emplace(live->id, live);
    return live;
  }

  /// The session as `caller` may see it: another owner's is absent (404), as an unknown one.
  std::shared_ptr<Live> find(const std::string& id, const Caller& caller) {
    std::lock_guard lock(mutex_);
    expire_idle();
    const auto found = sessions_.find(id);
    if (found == sessions_.end() || !visible_to(caller, found->second->owner)) {
      throw core::Error(core::ErrorCode::not_found, "no session '" + id + "'", {{"id", id}});
    }
    found->second->last_used = Clock::now();
    return found->second;
  }

  /// The session if it is still there, or null (for its WebSockets, which hold no reference to it).
  std::shared_ptr<Live> find_if_live(const std::string& id) {
    std::lock_guard lock(mutex_);
    const auto found = sessions_.find(id);
    if (found == sessions_.end()) return nullptr;
    found->second->last_used = Clock::now();
    return found->second;
  }

  void remove(const std::string& id, const Caller& caller) {
    std::lock_guard lock(mutex_);
    const auto found = sessions_.find(id);
    if (found == sessions_.end() || !visible_to(caller, found->second->owner)) {
      throw core::Error(core::ErrorCode::not_found, "no session '" + id + "'", {{"id", id}});
    }
    sessions_.erase(found);
  }

  std::vector<std::shared_ptr<Live>> all(const Caller& caller) {
    std::lock_guard lock(mutex_);
    expire_idle();
    std::vector<std::shared_ptr<Live>> list;
    for (const auto& [id, live] : sessions_) {
      if (visible_to(caller, live->owner)) list.push_back(live);
    }
    return list;
  }

 private:
  /// Idle sessions go (checked whenever the registry is used; the wall clock never enters a session);
  /// one with a WebSocket open is in use, even when its client is silent.
  void expire_idle() {
    const auto now = Clock::now();
    std::erase_if(sessions_, [&](const auto& entry) { return *entry.second->clients == 0 && now - entry.second->last_used > limits_.idle_timeout; });
  }

  /// Steps every realtime session to where the wall clock says it should be, kRealtimeTick apart. A
  /// session busy with a request is skipped this time; one that fell far behind skips ahead in wall
  /// time (it never steps more than kRealtimeMaxCatchUp at once).
  void step_realtime(std::stop_token stop) {
    auto next = Clock::now();
    while (!stop.stop_requested()) {
      next += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(kRealtimeTick));
      std::this_thread::sleep_until(next);
      std::vector<std::shared_ptr<Live>> realtime;
      {
        std::lock_guard lock(mutex_);
        for (const auto& [id, live] : sessions_) {
          if (live->mode == "realtime") realtime.push_back(live);
        }
      }
      const auto now = Clock::now();
      for (const auto& live : realtime) {
        std::unique_lock lock(live->mutex, std::try_to_lock);
        if (!lock) continue;
        const sim::Session& session = live->session();
        const double dt = session.model().dt;
        const double elapsed = std::chrono::duration<double>(now - live->realtime_origin).count() * live->realtime_factor;
        const auto due = live->realtime_origin_tick + static_cast<std::int64_t>(elapsed / dt);
        // At most what two ticks of wall clock are worth at this factor, and kRealtimeMaxCatchUp at least.
        const auto most = static_cast<std::int64_t>(std::max(kRealtimeMaxCatchUp, 2.0 * kRealtimeTick * live->realtime_factor) / dt);
        std::int64_t steps = due - session.state().tick;
        if (steps > most) {
          // Too far behind: start the clock again from here rather than rushing.
          steps = most;
          live->realtime_origin = now;
          live->realtime_origin_tick = session.state().tick + most;
        }
        for (std::int64_t i = 0; i < steps && !live->episode->over(); ++i) live->episode->tick();
      }
    }
  }

  SessionLimits limits_;
  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Live>> sessions_;
  std::jthread ticker_;  ///< last: it uses everything above
};

/// Most state frames per second a WebSocket subscription may ask for.
constexpr double kMaxPushRate = 60.0;

/// A laser scan as a binary WebSocket message: a 56-byte little-endian header, then the ranges as
/// float32 (REP 117: +inf beyond range_max, -inf closer than range_min). Layout in api/asyncapi.yaml.
std::string laser_frame(const sim::LaserReading& reading, double dt) {
  static_assert(std::endian::native == std::endian::little, "binary frames are written in the host's byte order");
  std::string frame(56 + 4 * reading.ranges.size(), '\0');
  char* out = frame.data();
  const auto put = [&](std::size_t offset, auto value) { std::memcpy(out + offset, &value, sizeof value); };
  std::memcpy(out, "HRLS", 4);
  put(4, std::uint16_t{1});   // format version
  put(6, std::uint16_t{56});  // header size
  put(8, std::int64_t{reading.tick});
  put(16, static_cast<double>(reading.tick) * dt);
  put(24, static_cast<float>(reading.pose.x));
  put(28, static_cast<float>(reading.pose.y));
  put(32, static_cast<float>(reading.pose.theta));
  put(36, static_cast<float>(reading.angle_min));
  put(40, static_cast<float>(reading.angle_increment));
  put(44, static_cast<float>(reading.range_min));
  put(48, static_cast<float>(reading.range_max));
  put(52, static_cast<std::uint32_t>(reading.ranges.size()));
  for (std::size_t i = 0; i < reading.ranges.size(); ++i) put(56 + 4 * i, static_cast<float>(reading.ranges[i]));
  return frame;
}

/// A robot's laser reading by sensor name (the first laser when empty), as a binary frame.
std::string laser_of(const sim::Session& session, const std::string& robot, const std::string& sensor) {
  const int agent = session.model().find_agent(robot);
  const sim::RobotRuntime* runtime = agent < 0 ? nullptr : session.robot_runtime(session.agent_id(robot));
  if (!runtime) throw core::Error(core::ErrorCode::not_found, "no robot with a model named '" + robot + "'", {{"pointer", "/robot"}});
  for (const auto& laser : runtime->lasers) {
    if (sensor.empty() || laser.reading.sensor == sensor) return laser_frame(laser.reading, session.model().dt);
  }
  throw core::Error(core::ErrorCode::not_found, "robot '" + robot + "' has no laser" + (sensor.empty() ? "" : " named '" + sensor + "'"),
                    {{"pointer", sensor.empty() ? "/robot" : "/sensor"}});
}

/// A camera's name, kind, image size, intrinsics, range, rate and pose (position and quaternion x, y, z, w).
json camera_json(const sim::CameraInfo& info) {
  const render::Camera& c = info.camera;
  const Eigen::Quaterniond q(c.pose.rotation());
  json camera = {{"name", info.name}, {"kind", info.kind}, {"width", c.width}, {"height", c.height}, {"near", c.near}, {"far", c.far},
                 {"rate", info.rate},
                 {"pose", {{"position", {c.pose.translation().x(), c.pose.translation().y(), c.pose.translation().z()}},
                           {"orientation", {q.x(), q.y(), q.z(), q.w()}}}}};
  if (c.orthographic_width > 0.0) {
    camera["orthographic_width"] = c.orthographic_width;
  } else {
    camera["fx"] = c.fx, camera["fy"] = c.fy, camera["cx"] = c.cx, camera["cy"] = c.cy;
  }
  return camera;
}

/// A binary RGB-D frame of a camera, as a deferred answer: the scene is taken now (the caller holds
/// the session's lock), the worker pool draws it.
Response camera_frame(const sim::Session& session, const std::string& name, int width, int height, bool ids) {
  sim::CameraInfo camera = sim::camera_of(session, name, width, height);
  render::Scene scene = sim::scene_for(session, camera);
  return Response::later([scene = std::move(scene), camera = std::move(camera), tick = session.state().tick, time = session.time(), ids] {
    return Response{200, kBinaryContentType, camera_message(render::render_on_this_thread(scene, camera.camera), camera, tick, time, ids), {}, {}};
  });
}

/// A session's WebSocket: lockstep messages, one answer each, in order.
///   {"type": "step", "n": 1}        → {"type": "step", …status, events, terminated, truncated}
///   {"type": "commands", "commands": [...]} → {"type": "commands", "applied", "tick"}
///   {"type": "state", "events_since": 0}    → {"type": "state", …}
///   {"type": "sensors", "robot": "robot"}   → {"type": "sensors", …}
///   {"type": "laser", "robot": "robot", "sensor": "base_laser"} → a binary laser frame
///   {"type": "camera", "camera": "robot.head_rgbd", "width", "height", "ids"} → a binary RGB-D frame
///   {"type": "subscribe", "rate": 10, "camera": {"name", "width", "height", "ids"}?}
///     → {"type": "subscribed", "rate", "camera"}, then state frames pushed at that rate (0 stops
///     them): {"type": "state_frame", …state, new events, dropped_frames}, each followed by a binary
///     RGB-D frame of the camera when one was asked for
/// A wrong message gets {"type": "error", "error": {code, message, details}} and the socket stays open.
class SessionSocket : public WebSocketPeer {
 public:
  /// Holds no reference to the session: a deleted one is freed, and the socket then closes.
  SessionSocket(std::shared_ptr<Registry> registry, const std::shared_ptr<Live>& live, Caller caller)
      : registry_(std::move(registry)), id_(live->id), clients_(live->clients), caller_(std::move(caller)) {
    ++*clients_;
  }
  ~SessionSocket() override { --*clients_; }

  std::string close_reason() const override { return registry_->find_if_live(id_) ? "" : "session " + id_ + " ended"; }

  Response on_message(const std::string& text) override {
    try {
      Request message;
      message.body = text;
      json body = json_object_body(message);
      if (body.contains("type") && !body["type"].is_string()) {
        throw core::Error(core::ErrorCode::bad_request, "type: a string", {{"pointer", "/type"}});
      }
      const std::string type = body.value("type", "");
      body.erase("type");
      const auto live = registry_->find(id_, caller_);
      if (caller_.read_only && (type == "step" || type == "commands" || type == "snapshot" || type == "restore")) {
        throw core::Error(core::ErrorCode::forbidden, "this socket's token may only read", {{"pointer", "/type"}});
      }
      if (type == "step") {
        refuse_unknown_keys(body, {"n", "action"});
        const auto steps = integer_field(body, "n", 1, kMaxStepsPerRequest, 1);
        const auto action = action_of(body);
        check_lockstep(*live);
        return Response::later([live, steps, action] {
          try {
            std::lock_guard lock(live->mutex);
            return reply("step", step_session(*live, steps, action));
          } catch (const core::Error& e) {
            return failure(e);
          }
        });
      }
      if (type == "commands") {
        refuse_unknown_keys(body, {"commands"});
        if (!body.contains("commands") || !body["commands"].is_array()) {
          throw core::Error(core::ErrorCode::bad_request, "commands: a list of commands is required", {{"pointer", "/commands"}});
        }
        return answer_locked(live, [commands = body["commands"]](Live& session) { return reply("commands", give_commands(session, commands)); });
      }
      if (type == "snapshot") {
        refuse_unknown_keys(body, {});
        return answer_locked(live, [](Live& session) { return reply("snapshot", take_snapshot(session)); });
      }
      if (type == "restore") {
        return Response::later([live, body] {
          try {
            std::lock_guard lock(live->mutex);
            return reply("restore", restore_snapshot(*live, body));
          } catch (const core::Error& e) {
            return failure(e);
          }
        });
      }
      if (type == "sensors") {
        refuse_unknown_keys(body, {"robot"});
        if (!body.contains("robot") || !body["robot"].is_string()) {
          throw core::Error(core::ErrorCode::bad_request, "robot: a robot's id is required", {{"pointer", "/robot"}});
        }
        return answer_locked(live, [robot = body["robot"].get<std::string>()](Live& session) { return reply("sensors", sensors_of(session.session(), robot)); });
      }
      if (type == "laser") {
        refuse_unknown_keys(body, {"robot", "sensor"});
        if (!body.contains("robot") || !body["robot"].is_string()) {
          throw core::Error(core::ErrorCode::bad_request, "robot: a robot's id is required", {{"pointer", "/robot"}});
        }
        if (body.contains("sensor") && !body["sensor"].is_string()) {
          throw core::Error(core::ErrorCode::bad_request, "sensor: a laser's name", {{"pointer", "/sensor"}});
        }
        return answer_locked(live, [robot = body["robot"].get<std::string>(), sensor = body.value("sensor", "")](Live& session) {
          return Response{200, kBinaryContentType, laser_of(session.session(), robot, sensor), {}, {}};
        });
      }
      if (type == "camera") {
        refuse_unknown_keys(body, {"camera", "width", "height", "ids"});
        if (!body.contains("camera") || !body["camera"].is_string()) {
          throw core::Error(core::ErrorCode::bad_request, "camera: a camera's name is required", {{"pointer", "/camera"}});
        }
        const auto width = static_cast<int>(integer_field(body, "width", 16, kMaxFrameSize, 0));
        const auto height = static_cast<int>(integer_field(body, "height", 16, kMaxFrameSize, 0));
        if (body.contains("ids") && !body["ids"].is_boolean()) throw core::Error(core::ErrorCode::bad_request, "ids: true or false", {{"pointer", "/ids"}});
        return answer_locked(live, [camera = body["camera"].get<std::string>(), width, height, ids = body.value("ids", false)](Live& session) {
          return camera_frame(session.session(), camera, width, height, ids);
        });
      }
      if (type == "subscribe") {
        refuse_unknown_keys(body, {"rate", "camera"});
        if (!body.contains("rate") || !body["rate"].is_number() || !(body["rate"].get<double>() >= 0.0) ||
            body["rate"].get<double>() > kMaxPushRate) {
          throw core::Error(core::ErrorCode::bad_request, "rate: frames per second from 0 (stop) to " + std::to_string(static_cast<int>(kMaxPushRate)),
                            {{"pointer", "/rate"}});
        }
        std::optional<CameraSubscription> camera;
        if (body.contains("camera") && !body["camera"].is_null()) {
          const json& asked = body["camera"];
          if (!asked.is_object() || !asked.contains("name") || !asked["name"].is_string()) {
            throw core::Error(core::ErrorCode::bad_request, "camera: {name, width, height, ids}", {{"pointer", "/camera"}});
          }
          refuse_unknown_keys(asked, {"name", "width", "height", "ids"}, "/camera");
          camera = CameraSubscription{asked["name"], static_cast<int>(integer_field(asked, "width", 16, kMaxFrameSize, 0, "/camera")),
                                      static_cast<int>(integer_field(asked, "height", 16, kMaxFrameSize, 0, "/camera")), false};
          if (asked.contains("ids") && !asked["ids"].is_boolean()) throw core::Error(core::ErrorCode::bad_request, "ids: true or false", {{"pointer", "/camera/ids"}});
          camera->ids = asked.value("ids", false);
          // An unknown camera is refused now, unless the session is busy (then the first push drops it).
          if (std::unique_lock lock(live->mutex, std::try_to_lock); lock) sim::camera_of(live->session(), camera->name, camera->width, camera->height);
        }
        rate_ = body["rate"].get<double>();
        camera_ = rate_ > 0.0 ? camera : std::nullopt;  // rate 0 stops both kinds of frame
        json answer = {{"rate", rate_}, {"camera", nullptr}};
        if (camera_) answer["camera"] = {{"name", camera_->name}, {"width", camera_->width}, {"height", camera_->height}, {"ids", camera_->ids}};
        return reply("subscribed", answer);
      }
      if (type == "state") {
        refuse_unknown_keys(body, {"events_since"});
        const auto since = integer_field(body, "events_since", 0, std::numeric_limits<std::int64_t>::max(), 0);
        return answer_locked(live, [since](Live& session) { return reply("state", state_of(session, since)); });
      }
      throw core::Error(core::ErrorCode::bad_request, "type must be step, commands, snapshot, restore, state, sensors, laser, camera or subscribe", {{"pointer", "/type"}});
    } catch (const core::Error& e) {
      return failure(e);
    } catch (const json::exception& e) {
      return failure(wrong_type(e));
    }
  }

  double push_rate() const override { return rate_; }

  std::vector<Response> push_frames(std::uint64_t dropped) override {
    const std::shared_ptr<Live> live = registry_->find_if_live(id_);
    if (!live) {
      rate_ = 0.0;  // the session is gone
      return {};
    }
    std::unique_lock lock(live->mutex, std::try_to_lock);
    if (!lock) return {};  // stepping: the next frame will show it
    const auto& events = live->session().state().events;
    const bool reset = live->generation != pushed_generation_;
    if (reset) {
      events_pushed_ = 0;
      pushed_generation_ = live->generation;
    }
    const std::int64_t tick = live->session().state().tick;
    if (!reset && tick == pushed_tick_ && events_pushed_ == events.size()) return {};  // nothing new
    json frame = state_of(*live, std::numeric_limits<std::int64_t>::max());
    json fresh = json::array();
    for (std::size_t e = events_pushed_; e < events.size(); ++e) fresh.push_back(event_json(events[e]));
    frame["events"] = fresh;
    frame["dropped_frames"] = dropped;
    frame["type"] = "state_frame";
    events_pushed_ = events.size();
    pushed_tick_ = tick;
    std::vector<Response> frames{Response::json(200, frame)};
    if (camera_) {
      try {
        frames.push_back(camera_frame(live->session(), camera_->name, camera_->width, camera_->height, camera_->ids));
      } catch (const core::Error&) {
        camera_.reset();  // the robot carrying it left the session
      }
    }
    return frames;
  }

 private:
  /// locked(), with errors answered as WebSocket error messages wherever the work runs.
  static Response answer_locked(std::shared_ptr<Live> live, std::function<Response(Live&)> work) {
    return locked(std::move(live), [work = std::move(work)](Live& session) {
      try {
        return work(session);
      } catch (const core::Error& e) {
        return failure(e);
      } catch (const json::exception& e) {
        return failure(wrong_type(e));
      }
    });
  }

  /// A value of the wrong JSON type somewhere in a message (the router says the same of a REST body).
  static core::Error wrong_type(const json::exception& e) {
    return core::Error(core::ErrorCode::bad_request, std::string("invalid message: ") + e.what());
  }

  static Response reply(const char* type, json body) {
    body["type"] = type;
    return Response::json(200, body);
  }
  static Response failure(const core::Error& error) {
    json body = error.to_json();
    body["type"] = "error";
    return Response::json(http_status(error.code()), body);
  }

  std::shared_ptr<Registry> registry_;
  std::string id_;
  std::shared_ptr<std::atomic<int>> clients_;  ///< the session's count of connected clients, shared with it
  Caller caller_;
  // Touched on the connection's strand only.
  double rate_ = 0.0;              ///< state frames per second subscribed to
  struct CameraSubscription {
    std::string name;
    int width = 0, height = 0;
    bool ids = false;
  };
  std::optional<CameraSubscription> camera_;  ///< a camera frame follows each state frame
  std::size_t events_pushed_ = 0;  ///< events before this index were in a frame
  std::int64_t pushed_tick_ = -1;
  std::uint64_t pushed_generation_ = 0;  ///< the session's resets when the last frame was pushed
};

/// The input that places an agent or object by name at a pose {x, y, z, roll, pitch, yaw} (checked; `at`
/// is its JSON pointer prefix): seed 000's uniform pose interface. People and robots stay upright on
/// the floor; a place off the floor is refused when the input is given.
episode::Episode::Input place(const sim::Session& session, const std::string& name, const json& body, const std::string& at) {
  if (!body.is_object()) throw core::Error(core::ErrorCode::bad_request, "a pose is an object {x, y, z, roll, pitch, yaw}", {{"pointer", at}});
  for (const auto& [key, unused] : body.items()) {
    if (key != "x" && key != "y" && key != "z" && key != "roll" && key != "pitch" && key != "yaw") {
      throw core::Error(core::ErrorCode::bad_request, "unknown field '" + key + "'", {{"pointer", at + "/" + key}});
    }
  }
  const double x = number_of(body, "x", at), y = number_of(body, "y", at);
  const auto optional = [&](const char* key) { return body.contains(key) ? number_of(body, key, at) : 0.0; };
  const double z = optional("z"), roll = optional("roll"), pitch = optional("pitch"), yaw = optional("yaw");
  if (session.model().find_agent(name) >= 0) {
    for (const char* key : {"z", "roll", "pitch"}) {
      if (optional(key) != 0.0) {
        throw core::Error(core::ErrorCode::bad_request, std::string(key) + ": agents stand upright on the floor", {{"pointer", at + "/" + key}});
      }
    }
    const int agent = session.index_of(session.agent_id(name));
    return [agent, x, y, yaw](sim::Session& to) { to.place_agent(to.agent_at(agent), {x, y, yaw}); };
  }
  const auto& objects = session.model().objects;
  const auto found = std::find_if(objects.begin(), objects.end(), [&](const scenario::MovableObject& o) { return o.name == name; });
  if (found == objects.end()) throw core::Error(core::ErrorCode::not_found, "no agent or object '" + name + "'", {{"name", name}, {"pointer", at}});
  const int object = static_cast<int>(found - objects.begin());
  const Eigen::Isometry3d pose = robots::to_isometry({x, y, z, roll, pitch, yaw});
  return [object, pose](sim::Session& to) { to.place_object(object, pose); };
}

/// A 503 for too many sessions carries Retry-After.
Response refused(const core::Error& error) {
  Response response = Response::error(error);
  if (error.code() == core::ErrorCode::unavailable) response.headers.emplace_back("Retry-After", std::to_string(kSessionRetryAfter));
  return response;
}

}  // namespace

void add_session_routes(Router& router, std::shared_ptr<ScenarioCatalogue> catalogue, SessionLimits limits, std::shared_ptr<TicketBook> tickets) {
  auto registry = std::make_shared<Registry>(limits);

  router.add("POST", "/api/v1/sessions", [catalogue, registry](const Request& request) {
    const json body = json_object_body(request);
    refuse_unknown_keys(body, {"scenario", "seed", "mode", "realtime_factor", "controller"});
    if (!body.contains("scenario") || !body["scenario"].is_string()) {
      throw core::Error(core::ErrorCode::bad_request, "scenario: the id of a scenario is required", {{"pointer", "/scenario"}});
    }
    const std::string scenario = body["scenario"];
    const std::int64_t seed = integer_field(body, "seed", 0, kMaxSeed, 0);
    const std::string mode = body.contains("mode") && body["mode"].is_string() ? body["mode"].get<std::string>() : body.contains("mode") ? "" : "lockstep";
    if (mode != "lockstep" && mode != "realtime") {
      throw core::Error(core::ErrorCode::bad_request, "mode: lockstep or realtime", {{"pointer", "/mode"}});
    }
    double factor = 1.0;
    if (body.contains("realtime_factor")) {
      const json& value = body["realtime_factor"];
      if (mode != "realtime" || !value.is_number() || !(value.get<double>() > 0.0) || value.get<double>() > kMaxRealtimeFactor) {
        throw core::Error(core::ErrorCode::bad_request,
                          "realtime_factor: for a realtime session, simulated seconds per second, above 0 and at most " +
                              std::to_string(static_cast<int>(kMaxRealtimeFactor)),
                          {{"pointer", "/realtime_factor"}});
      }
      factor = value.get<double>();
    }
    // Compiling an upload and building the session's world (physics, sensors) are work for the pool.
    return Response::later([catalogue, registry, body, scenario, seed, mode, factor, caller = request.caller] {
      const auto entry = catalogue->find(scenario, caller);
      if (!entry || !entry->source.model) {
        throw core::Error(core::ErrorCode::not_found, "no scenario '" + scenario + "'", {{"pointer", "/scenario"}, {"id", scenario}});
      }
      std::shared_ptr<const scenario::Model> model = entry->source.model;
      std::optional<json> controller;
      if (body.contains("controller") && !body["controller"].is_null()) {
        json errors = json::array();
        model = runs::with_controller(entry->source.document, body["controller"], catalogue->options(*entry).load, errors).model;
        runs::throw_if_problems(errors);
        controller = body["controller"];
      }
      try {
        const auto live = registry->create(scenario, model, seed, mode, factor, controller, caller.owner);
        std::lock_guard lock(live->mutex);
        Response response = Response::json(201, status_of(*live));
        response.headers.emplace_back("Location", "/api/v1/sessions/" + live->id);
        return response;
      } catch (const core::Error& error) {
        return refused(error);
      }
    });
  });

  router.add("GET", "/api/v1/sessions", [registry](const Request& request) {
    // Each session's lock is taken: on the pool, where waiting behind a long step holds no I/O thread.
    return Response::later([registry, caller = request.caller] {
      json items = json::array();
      for (const auto& live : registry->all(caller)) {
        std::lock_guard lock(live->mutex);
        items.push_back(status_of(*live));
      }
      return Response::json(200, {{"items", items}});
    });
  });

  router.add_websocket("/api/v1/sessions/{id}/ws", [registry](const Request& request) -> std::shared_ptr<WebSocketPeer> {
    // 404 for an unknown session, before the upgrade; the Origin was checked by the guard.
    return std::make_shared<SessionSocket>(registry, registry->find(request.path_params.at("id"), request.caller), request.caller);
  });

  router.add("POST", "/api/v1/sessions/{id}/ws-ticket", [registry, tickets](const Request& request) {
    const std::string& id = request.path_params.at("id");
    registry->find(id, request.caller);
    const std::string ticket = tickets->issue(id, request.caller);
    return Response::json(201, {{"ticket", ticket},
                                {"expires_in", kTicketLifetime.count()},
                                {"url", "/api/v1/sessions/" + id + "/ws?ticket=" + ticket}});
  });

  router.add("GET", "/api/v1/sessions/{id}", [registry](const Request& request) {
    return locked(registry->find(request.path_params.at("id"), request.caller), [](Live& live) { return Response::json(200, status_of(live)); });
  });

  router.add("DELETE", "/api/v1/sessions/{id}", [registry](const Request& request) {
    registry->remove(request.path_params.at("id"), request.caller);
    return Response{204, "application/json", "", {}, {}};
  });

  router.add("POST", "/api/v1/sessions/{id}/snapshots", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    refuse_unknown_keys(json_object_body(request), {});
    return locked(live, [](Live& session) { return Response::json(201, take_snapshot(session)); });
  });

  router.add("GET", "/api/v1/sessions/{id}/snapshots", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    return locked(live, [](Live& session) {
      json items = json::array();
      for (const auto& [id, snapshot] : session.snapshots) items.push_back(snapshot_json(id, snapshot));
      return Response::json(200, {{"items", items}, {"max_snapshots", kMaxSnapshots}});
    });
  });

  router.add("DELETE", "/api/v1/sessions/{id}/snapshots/{snapshot}", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    return locked(live, [name = request.path_params.at("snapshot")](Live& session) {
      if (session.snapshots.erase(name) == 0) throw core::Error(core::ErrorCode::not_found, "session " + session.id + " has no snapshot '" + name + "'");
      return Response{204, "application/json", "", {}, {}};
    });
  });

  router.add("POST", "/api/v1/sessions/{id}/restore", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    const json body = json_object_body(request);
    // Restoring simulates again up to the snapshot: work for the pool.
    return Response::later([live, body] {
      std::lock_guard lock(live->mutex);
      return Response::json(200, restore_snapshot(*live, body));
    });
  });

  router.add("GET", "/api/v1/sessions/{id}/state", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    const auto since = integer_query(request, "events_since", 0, std::numeric_limits<std::int64_t>::max(), 0);
    return locked(live, [since](Live& session) { return Response::json(200, state_of(session, since)); });
  });

  router.add("GET", "/api/v1/sessions/{id}/robots/{robot}/sensors", [registry](const Request& request) {
    return locked(registry->find(request.path_params.at("id"), request.caller), [robot = request.path_params.at("robot")](Live& live) {
      return Response::json(200, sensors_of(live.session(), robot));
    });
  });

  router.add("GET", "/api/v1/sessions/{id}/poses", [registry](const Request& request) {
    return locked(registry->find(request.path_params.at("id"), request.caller), [](Live& live) { return Response::json(200, poses_of(live.session())); });
  });

  router.add("PUT", "/api/v1/sessions/{id}/poses/{name}", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    return locked(live, [body = json_object_body(request), name = request.path_params.at("name")](Live& session) {
      session.episode->give(place(session.session(), name, body, ""));
      return Response::json(200, poses_of(session.session()));
    });
  });

  router.add("POST", "/api/v1/sessions/{id}/reset", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    const json body = json_object_body(request);
    refuse_unknown_keys(body, {"seed", "options"});
    const json options = body.value("options", json::object());
    if (!options.is_object()) throw core::Error(core::ErrorCode::bad_request, "options: an object", {{"pointer", "/options"}});
    for (const auto& [key, unused] : options.items()) {
      if (key != "poses") throw core::Error(core::ErrorCode::bad_request, "options: unknown field '" + key + "'", {{"pointer", "/options/" + key}});
    }
    const json poses = options.value("poses", json::object());
    if (!poses.is_object()) throw core::Error(core::ErrorCode::bad_request, "options.poses: {name: pose}", {{"pointer", "/options/poses"}});
    // A fresh session is built: work for the pool.
    return Response::later([live, body, poses] {
      std::lock_guard lock(live->mutex);
      const std::int64_t seed = integer_field(body, "seed", 0, kMaxSeed, live->seed);
      // A fresh session of the same scenario: everything starts again from tick 0, then the poses given
      // are set (all or none: a bad one leaves the old session as it was).
      auto fresh = std::make_unique<Live>();
      fresh->seed = seed;
      fresh->recording_memory = live->recording_memory;
      fresh->start(live->session().shared_model());
      for (const auto& [name, pose] : poses.items()) {
        fresh->episode->give(place(fresh->session(), name, pose, "/options/poses/" + core::pointer_token(name)));
      }
      live->seed = seed;
      ++live->generation;
      live->episode = std::move(fresh->episode);
      live->snapshots.clear();
      live->events_reported = 0;
      live->realtime_origin = fresh->realtime_origin;
      live->realtime_origin_tick = 0;
      // Gymnasium's reset: the first observation and info, with the session's status.
      json reply = status_of(*live);
      add_observation(*live, reply);
      return Response::json(200, reply);
    });
  });

  router.add("POST", "/api/v1/sessions/{id}/commands", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    const json body = json_object_body(request);
    refuse_unknown_keys(body, {"commands"});
    if (!body.contains("commands") || !body["commands"].is_array()) {
      throw core::Error(core::ErrorCode::bad_request, "commands: a list of commands is required", {{"pointer", "/commands"}});
    }
    return locked(live, [commands = body["commands"]](Live& session) { return Response::json(200, give_commands(session, commands)); });
  });

  router.add("POST", "/api/v1/sessions/{id}/step", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    const json body = json_object_body(request);
    refuse_unknown_keys(body, {"n", "action"});
    const auto steps = integer_field(body, "n", 1, kMaxStepsPerRequest, 1);
    const auto action = action_of(body);
    check_lockstep(*live);
    // Stepping may take long: on the worker pool, never on an I/O thread.
    return Response::later([live, steps, action] {
      std::lock_guard lock(live->mutex);
      return Response::json(200, step_session(*live, steps, action));
    });
  });

  router.add("GET", "/api/v1/sessions/{id}/metrics", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    // Computed from every step so far, on the worker pool: a long session has many.
    return Response::later([live] {
      std::lock_guard lock(live->mutex);
      json metrics = json::object(), null_reasons = json::object();
      for (const metrics::MetricValue& metric : metrics::compute_episode_metrics(live->episode->recording(live->session().state().finished ? "" : "running"))) {
        metrics[metric.key] = metric.value ? json(*metric.value) : json();
        if (!metric.value) null_reasons[metric.key] = metric.null_reason;
      }
      return Response::json(200, {{"id", live->id},
                                  {"tick", live->session().state().tick},
                                  {"recorded_until_tick", live->episode->recorder()->recorded_until()},
                                  {"recording_stopped", live->episode->recorder()->stopped().empty() ? json() : json(live->episode->recorder()->stopped())},
                                  {"time", live->session().time()},
                                  {"metrics", metrics},
                                  {"null_reasons", null_reasons}});
    });
  });

  router.add("GET", "/api/v1/sessions/{id}/frames/{camera}", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    const FrameRequest asked = frame_request(request);
    // The scene is copied under the session's lock; drawing happens after, on the worker pool.
    return locked(live, [asked, name = request.path_params.at("camera")](Live& session) {
      const sim::CameraInfo info = sim::camera_of(session.session(), name, asked.width, asked.height);
      return Response::later([scene = sim::scene_for(session.session(), info), camera = info.camera, asked] {
        return encode_frame(render::render_on_this_thread(scene, camera), asked);
      });
    });
  });

  router.add("GET", "/api/v1/sessions/{id}/cameras", [registry](const Request& request) {
    return locked(registry->find(request.path_params.at("id"), request.caller), [](Live& live) {
      json cameras = json::array();
      for (const sim::CameraInfo& info : sim::cameras_of(live.session())) cameras.push_back(camera_json(info));
      return Response::json(200, {{"id", live.id}, {"tick", live.session().state().tick}, {"cameras", cameras},
                                  {"segmentation", sim::segmentation_legend(live.session())}});
    });
  });

  router.add("GET", "/api/v1/sessions/{id}/action_space", [registry](const Request& request) {
    return locked(registry->find(request.path_params.at("id"), request.caller), [](Live& live) {
      if (!live.environment()) throw core::Error(core::ErrorCode::conflict, "this session has no robot that can act");
      return Response::json(200, space_json(live.environment()->action_space()));
    });
  });

  router.add("GET", "/api/v1/sessions/{id}/observation_space", [registry](const Request& request) {
    return locked(registry->find(request.path_params.at("id"), request.caller), [](Live& live) {
      if (!live.environment()) throw core::Error(core::ErrorCode::conflict, "this session has no robot to observe");
      return Response::json(200, space_json(live.environment()->observation_space(), live.environment()->image()));
    });
  });
}

}  // namespace hrisim::http
