#include "http/session_views.hpp"

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/error.hpp"
#include "http/frames.hpp"
#include "metrics/episode_metrics.hpp"
#include "render/image_codec.hpp"
#include "sim/activities.hpp"
#include "sim/seats.hpp"

namespace hrisim::http {

using nlohmann::json;

/// The events of tick `first` and later; they are kept in tick order, so only the new ones are looked at.
static json events_since(const sim::Session& session, std::int64_t first) {
  const auto& events = session.state().events;
  auto begin = events.end();
  while (begin != events.begin() && std::prev(begin)->tick >= first) --begin;
  json list = json::array();
  for (auto event = begin; event != events.end(); ++event) list.push_back(event_json(*event));
  return list;
}

/// Status of a session (its lock held).
namespace {

/// The activity a person living on their own is doing, or null.
json activity_name(const sim::Session& session, int agent) {
  const sim::AgentState& self = session.state().agents[agent];
  const scenario::ActivityModel* living = sim::activity_model_of(session.model(), session.state(), agent);
  return living && self.living.activity.valid() ? json(living->activities[self.living.activity.value].name) : json();
}

/// The scenario clock's time of day and day, when the scenario keeps one.
json clock_reading(const sim::Session& session) {
  if (!session.model().clock) return nullptr;
  const scenario::Clock clock = sim::session_clock(session.model(), session.state());
  return {{"time_of_day", scenario::format_time_of_day(scenario::time_of_day(clock, session.time()))},
          {"day", scenario::day_of(clock, session.time())},
          {"speed", clock.speed}};
}

}  // namespace

void write_status(core::JsonWriter& out, const LiveSession& live) {
  const sim::Session& session = live.session();
  const sim::State& state = session.state();
  const bool in_step = state.current_step < static_cast<int>(session.model().steps.size());
  const auto current_step = [&] {
    if (in_step) {
      out.begin_object().key("index").value(state.current_step).key("name").value(session.model().steps[state.current_step].name).end_object();
    } else {
      out.null();
    }
  };
  out.key("id").value(live.id).key("scenario").value(live.scenario).key("seed").value(live.seed).key("mode").value(to_string(live.mode));
  out.key("realtime_factor");
  live.mode == Mode::realtime ? out.value(live.realtime_factor) : out.null();
  out.key("controller");
  live.controller ? out.value(*live.controller) : out.null();
  out.key("connected_clients").value(live.clients->load());
  out.key("episode");
  live.episode_id.empty() ? out.null() : out.value(live.episode_id);
  out.key("unwatched_grace");
  live.unwatched_grace ? out.value(static_cast<std::int64_t>(live.unwatched_grace->count())) : out.null();
  out.key("tick").value(state.tick).key("time").value(session.time()).key("dt").value(session.model().dt);
  out.key("clock").value(clock_reading(session));
  out.key("status").value(state.finished ? "finished" : "running");
  out.key("termination");
  state.finished ? out.value(sim::to_string(state.termination)) : out.null();
  out.key("current_step");
  current_step();
  out.key("step");  // the former name, kept for one version
  current_step();
  out.key("task");
  if (session.model().task && live.environment()) {
    out.begin_object().key("name").value(session.model().task->name).key("step_ticks").value(live.environment()->step_ticks(session));
    out.key("terminated").value(live.environment()->terminated(session)).end_object();
  } else {
    out.null();
  }
  out.key("state_hash").value(session.state_hash_hex());
}

json status_of(const LiveSession& live) {
  core::JsonWriter out;
  out.begin_object();
  write_status(out, live);
  out.end_object();
  return json::parse(out.text());
}

/// Every agent's pose and motion, requests waiting for an answer, and the events since a tick.
/// The waypoints an agent still has to pass, from where it is: [[x, y], …]; empty when it stands.
static json path_ahead(const sim::AgentState& agent) {
  json points = json::array();
  if (!agent.navigation.under_way) return points;
  points.push_back({agent.position.x(), agent.position.y()});
  for (std::size_t w = agent.navigation.path_index; w < agent.navigation.path.size(); ++w) points.push_back({agent.navigation.path[w].x(), agent.navigation.path[w].y()});
  return points;
}

json state_of(const LiveSession& live, std::int64_t events_since_tick) {
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
                      {"motion", agent.animation.motion ? json(agent.animation.motion->name()) : json()},
                      {"activity", activity_name(session, static_cast<int>(i))},
                      {"room", agent.living.room.valid() ? json(session.model().rooms[agent.living.room.value].name) : json()},
                      {"behaviour", def.kind == scenario::AgentKind::human ? json(humans::behaviour_name(agent.reaction.behaviour.type)) : json()},
                      {"reacting_to", agent.reaction.reacting_to.valid() ? json(session.model().agents[agent.reaction.reacting_to.value].id) : json()},
                      {"seat", sim::held_by_seat(agent) ? json(session.model().seats[agent.seating.seat.value].name) : json()},
                      {"carrying", agent.carrying.object.valid() ? json(session.model().objects[agent.carrying.object.value].name) : json()},
                      {"queue", agent.queueing.queue.valid() ? json{{"name", session.model().queues[agent.queueing.queue.value].name},
                                                        {"place", agent.queueing.place >= 0 ? json(agent.queueing.place) : json()}}
                                                 : json()}});
  }
  json requests = json::array();
  for (const sim::OpenRequest& open : state.requests) {
    const std::string& routine = session.model().routines[open.routine].name;
    requests.push_back({{"robot", session.model().agents[open.robot].id}, {"routine", routine}, {"task", routine}});  // "task": the former name, for one version
  }
  json reply = status_of(live);
  reply["agents"] = agents;
  reply["requests"] = requests;
  reply["events"] = events_since(session, events_since_tick);
  return reply;
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
json space_json(const tasks::Space& space, const std::optional<tasks::ImageObservation>& image) {
  if (space.name == "Discrete") return {{"name", "Discrete"}, {"n", space.n}};
  json low = json::array(), high = json::array();
  for (const double value : space.low) low.push_back(number_or_infinity(value));
  for (const double value : space.high) high.push_back(number_or_infinity(value));
  json doc = {{"name", space.name}, {"shape", space.shape}, {"low", low}, {"high", high}, {"dtype", space.dtype}};
  if (image) doc["camera"] = {{"name", image->camera}, {"width", image->width}, {"height", image->height}};
  return doc;
}

/// A robot's latest sensor readings and its joints (the session's lock held).
/// A listening robot's array: its last block's place in the audio stream and the direction of arrival
/// (in the array link's frame and as a bearing in the map), null before the first reading or in silence.
static json microphones_json(const sim::RobotRuntime& runtime) {
  const sim::RobotRuntime::Hearing& hearing = *runtime.hearing;
  json direction = nullptr;
  if (hearing.reading) {
    const Eigen::Vector3d along = runtime.microphones_pose().rotation() * Eigen::Vector3d(std::cos(hearing.reading->azimuth), std::sin(hearing.reading->azimuth), 0.0);
    direction = {{"tick", hearing.reading_tick}, {"azimuth", hearing.reading->azimuth}, {"bearing", std::atan2(along.y(), along.x())},
                 {"power", hearing.reading->power}};
  }
  return {{"link", hearing.microphones.array().link}, {"channels", hearing.block.channels}, {"sample_rate", sensors::kSampleRate},
          {"first_sample", hearing.block.first_sample}, {"samples", hearing.block.samples}, {"direction", direction},
          {"direction_tick", hearing.reading_tick}};
}

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
                      {"vx", person.velocity.x()}, {"vy", person.velocity.y()}, {"range", person.range}, {"bearing", person.bearing}, {"face_visible", person.face_visible}});
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
  const auto xyz = [](const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); };
  json imus = json::array();
  for (const auto& imu : runtime->imus) {
    const sim::ImuReading& reading = imu.reading;
    const Eigen::Quaterniond& q = reading.orientation;
    imus.push_back({{"sensor", reading.sensor}, {"tick", reading.tick}, {"orientation", {{"x", q.x()}, {"y", q.y()}, {"z", q.z()}, {"w", q.w()}}},
                    {"angular_velocity", xyz(reading.angular_velocity)}, {"linear_acceleration", xyz(reading.linear_acceleration)}});
  }
  json force_torque = json::array();
  for (const auto& sensor : runtime->force_torque_sensors) {
    const sim::ForceTorqueReading& reading = sensor.reading;
    force_torque.push_back({{"sensor", reading.sensor}, {"tick", reading.tick}, {"force", xyz(reading.force)}, {"torque", xyz(reading.torque)}});
  }
  const sim::OdometryReading& odometry = runtime->odometry_reading;
  json microphones = nullptr;
  if (runtime->hearing) microphones = microphones_json(*runtime);
  return {{"robot", name},
          {"tick", session.state().tick},
          {"lasers", lasers},
          {"people", {{"tick", runtime->people.tick}, {"detections", people}}},
          {"odometry", {{"tick", odometry.tick}, {"x", odometry.pose.x}, {"y", odometry.pose.y}, {"theta", odometry.pose.theta},
                        {"linear", odometry.twist.linear}, {"angular", odometry.twist.angular}}},
          {"imu", imus},
          {"force_torque", force_torque},
          {"joints", joints},
          {"gripper_closed", runtime->robot.gripper_closed()},
          {"contacts", contacts},
          {"microphones", microphones}};
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

/// Gymnasium's observation and info now: the observation null when it is a camera image (fetched as
/// a binary camera frame), info the tick, time and the last step's reward terms.
void write_observation(core::JsonWriter& out, const LiveSession& live) {
  const sim::Session& session = live.session();
  out.key("observation");
  if (live.environment() && !live.environment()->image()) {
    out.value(std::span<const double>(live.environment()->observe(session)));
  } else {
    out.null();
  }
  out.key("info").begin_object().key("tick").value(session.state().tick).key("time").value(session.time());
  if (live.environment()) out.members(live.environment()->info(session));
  out.end_object();
}

void add_observation(const LiveSession& live, json& reply) {
  core::JsonWriter out;
  out.begin_object();
  write_observation(out, live);
  out.end_object();
  reply.update(json::parse(out.text()));
}

json snapshot_json(const std::string& id, const episode::Episode::Snapshot& snapshot) {
  return {{"snapshot", id}, {"tick", snapshot.tick}, {"state_hash", sim::hash_hex(snapshot.state_hash)}};
}

json segmentation_legend(const sim::Session& session) {
  const scenario::Model& model = session.model();
  json legend = json::array();
  legend.push_back({{"id", sim::kFloorId}, {"kind", "floor"}, {"name", "floor"}});
  if (model.map_from_image) legend.push_back({{"id", sim::kWallsId}, {"kind", "walls"}, {"name", "map"}});
  if (!model.map_from_image) {
    for (std::size_t o = 0; o < model.obstacles.size(); ++o) {
      legend.push_back({{"id", sim::kObstacleIdBase + o}, {"kind", "obstacle"}, {"name", model.obstacles[o].name}});
    }
  }
  for (std::size_t d = 0; d < model.doors.size(); ++d) legend.push_back({{"id", sim::kDoorIdBase + d}, {"kind", "door"}, {"name", model.doors[d].name}});
  for (std::size_t o = 0; o < model.objects.size(); ++o) legend.push_back({{"id", sim::kObjectIdBase + o}, {"kind", "object"}, {"name", model.objects[o].name}});
  for (const sim::AgentId id : session.agent_ids()) {
    const int a = session.index_of(id);
    const scenario::AgentDef& def = model.agents[a];
    const sim::RobotRuntime* runtime = session.robot_runtime(id);
    if (!runtime) {
      legend.push_back({{"id", sim::kAgentIdBase + a}, {"kind", def.kind == scenario::AgentKind::human ? "human" : "robot"}, {"name", def.id}, {"agent", def.id}});
      continue;
    }
    const auto& links = runtime->robot.description().links;
    for (std::size_t l = 0; l < links.size(); ++l) {
      if (!links[l].collision) continue;
      legend.push_back({{"id", sim::kRobotLinkIdBase + a * 1000 + l}, {"kind", "robot_link"}, {"name", def.id + "/" + links[l].name}, {"agent", def.id}, {"link", links[l].name}});
    }
  }
  return legend;
}

/// A laser scan as a binary WebSocket message: a 56-byte little-endian header, then the ranges as
/// float32 (REP 117: +inf beyond range_max, -inf closer than range_min). Layout in api/asyncapi.yaml.
static std::string laser_frame(const sim::LaserReading& reading, double dt) {
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

std::string audio_of(const sim::Session& session, const std::string& robot) {
  static_assert(std::endian::native == std::endian::little, "binary frames are written in the host's byte order");
  const int agent = session.model().find_agent(robot);
  const sim::RobotRuntime* runtime = agent < 0 ? nullptr : session.robot_runtime(session.agent_id(robot));
  if (!runtime) throw core::Error(core::ErrorCode::not_found, "no robot with a model named '" + robot + "'", {{"pointer", "/robot"}});
  if (!runtime->hearing) {
    throw core::Error(core::ErrorCode::not_found, "robot '" + robot + "' does not listen: give it \"microphones\" in the scenario", {{"pointer", "/robot"}});
  }
  const sensors::AudioBlock& block = runtime->hearing->block;
  constexpr std::size_t kHeader = 48;
  std::string frame(kHeader + 4 * block.data.size(), '\0');
  char* out = frame.data();
  const auto put = [&](std::size_t offset, auto value) { std::memcpy(out + offset, &value, sizeof value); };
  std::memcpy(out, "HRAU", 4);
  put(4, std::uint16_t{1});  // format version
  put(6, static_cast<std::uint16_t>(kHeader));
  put(8, std::int64_t{session.state().tick});
  put(16, session.time());
  put(24, std::int64_t{block.first_sample});
  put(32, static_cast<std::uint32_t>(sensors::kSampleRate));
  put(36, static_cast<std::uint32_t>(block.channels));
  put(40, static_cast<std::uint32_t>(block.samples));
  put(44, std::uint32_t{0});
  if (!block.data.empty()) std::memcpy(out + kHeader, block.data.data(), 4 * block.data.size());
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
    return Response{200, kBinaryContentType, camera_message(scene, camera, tick, time, ids), {}, {}};
  });
}

std::function<render::Frame()> draw_later(const sim::Session& session, const std::string& name, int width, int height) {
  sim::CameraInfo camera = sim::camera_of(session, name, width, height);
  return [scene = sim::scene_for(session, camera), camera = std::move(camera)] { return render::render_on_this_thread(scene, camera.camera); };
}

json metrics_so_far(const LiveSession& live) {
  json metrics = json::object(), null_reasons = json::object();
  for (const metrics::MetricValue& metric : metrics::compute_episode_metrics(live.episode->recording(live.session().state().finished ? "" : "running"))) {
    metrics[metric.key] = metric.value ? json(*metric.value) : json();
    if (!metric.value) null_reasons[metric.key] = metric.null_reason;
  }
  return {{"id", live.id},
          {"tick", live.session().state().tick},
          {"recorded_until_tick", live.episode->recorder()->recorded_until()},
          {"recording_stopped", live.episode->recorder()->stopped().empty() ? json() : json(live.episode->recorder()->stopped())},
          {"time", live.session().time()},
          {"metrics", metrics},
          {"null_reasons", null_reasons}};
}

Response scene_frame(const sim::Session& session, bool all) {
  return Response{200, kBinaryContentType, scene_message(sim::scene_of(session), session.state().tick, session.time(), all), {}, {}};
}

}  // namespace hrisim::http
