#include "http/foxglove_socket.hpp"

#include <algorithm>
#include <map>
#include <span>
#include <string_view>

#include "core/bounded_json.hpp"
#include "core/build_info.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "http/foxglove_messages.hpp"
#include "http/foxglove_protocol.hpp"
#include "http/frames.hpp"
#include "http/request_helpers.hpp"
#include "http/session_inputs.hpp"
#include "http/session_limits.hpp"
#include "http/session_views.hpp"
#include "live/watcher.hpp"
#include "render/image_codec.hpp"
#include "sim/camera_scene.hpp"
#include "sim/session.hpp"

namespace hrisim::http {
namespace {

using nlohmann::json;
namespace fg = foxglove;

/// How fast a socket streams, from its upgrade's query.
struct StreamSettings {
  double rate = 30.0;        ///< scene, frames, lasers, detections, events: messages per second at most
  double image_rate = 10.0;  ///< each subscribed camera's images per second
  int image_width = 0, image_height = 0;  ///< 0: the camera's own
};
constexpr double kMetricsRate = 1.0;
/// What moves in the scene is kept this many of its periods unless sent again.
constexpr double kMovingLifetime = 3.0;
/// Channels one client may advertise.
constexpr std::size_t kMaxClientChannels = 16;
/// The fixed part of the scene is sent again after a push was dropped, at most this often, s.
constexpr double kFixedSceneResend = 1.0;

/// What a channel carries.
enum class Feed { scene, transforms, laser, people, camera, depth, events, metrics };

struct FeedChannel {
  fg::Channel channel;
  Feed feed;
  std::string robot;   ///< laser, people
  std::string source;  ///< the laser's sensor, the camera's name
  double rate = 0.0;
};

struct Subscription {
  std::size_t channel = 0;  ///< index in the socket's channels
  Clock::time_point last_sent{};
  std::int64_t last_reading = -1;  ///< a laser's or detector's tick last sent
  bool fresh = true;               ///< nothing sent yet: its first message goes with the next push
};

/// The services, their ids as advertised.
constexpr std::uint32_t kStep = 1, kReset = 2, kSeek = 3;
const std::vector<fg::Service> kServices = {{kStep, "/hrisim/step", "hrisim.StepRequest", "hrisim.Status"},
                                            {kReset, "/hrisim/reset", "hrisim.ResetRequest", "hrisim.Status"},
                                            {kSeek, "/hrisim/seek", "hrisim.SeekRequest", "hrisim.Status"}};

std::uint32_t uint32_field(const json& object, const char* key, const std::string& where) {
  if (!object.is_object() || !object.contains(key) || !object[key].is_number_unsigned() || object[key].get<std::uint64_t>() > UINT32_MAX) {
    throw core::Error(core::ErrorCode::bad_request, where + "." + key + " must be an unsigned 32-bit integer");
  }
  return object[key].get<std::uint32_t>();
}

const json& array_field(const json& object, const char* key) {
  if (!object.contains(key) || !object[key].is_array()) throw core::Error(core::ErrorCode::bad_request, std::string(key) + " must be an array");
  return object[key];
}

Response text(const json& message) { return Response{200, "application/json", core::json_text(message), {}, {}}; }
Response binary(std::string bytes) { return Response{200, kBinaryContentType, std::move(bytes), {}, {}}; }
Response error_status(const std::string& message) { return text(fg::status(fg::Level::error, message)); }

/// A Twist-shaped JSON message ({linear: {x, y, z}, angular: {x, y, z}}) as a robot's velocity command:
/// linear.x forward and angular.z about the vertical (a differential drive's two).
json velocity_command(const std::string& robot, const std::string& payload) {
  const json twist = core::parse_bounded_json(payload, "the velocity");
  const auto number = [&](const char* part, const char* axis) {
    if (!twist.is_object() || !twist.contains(part) || !twist[part].is_object() || !twist[part].value(axis, json()).is_number()) {
      throw core::Error(core::ErrorCode::bad_request, "a velocity is a Twist in JSON, {\"linear\": {\"x\", \"y\", \"z\"}, \"angular\": {\"x\", \"y\", \"z\"}}; " +
                                                          std::string(part) + "." + axis + " is missing or not a number");
    }
    return twist[part][axis].get<double>();
  };
  return json::array({{{"robot", robot}, {"velocity", {{"linear", number("linear", "x")}, {"angular", number("angular", "z")}}}}});
}

class FoxgloveSocket : public WebSocketPeer {
 public:
  FoxgloveSocket(std::shared_ptr<Registry> registry, const std::shared_ptr<LiveSession>& live, Caller caller, std::string subprotocol,
                 StreamSettings settings)
      : registry_(registry), watcher_(std::move(registry), *live), caller_(std::move(caller)), subprotocol_(std::move(subprotocol)), settings_(settings) {}

  std::string subprotocol() const override { return subprotocol_; }
  std::string close_reason() const override { return watcher_.session_live() ? "" : "session " + watcher_.session_id() + " ended"; }
  double push_rate() const override { return std::max(settings_.rate, settings_.image_rate); }

  std::vector<Response> on_open() override {
    const auto live = registry_->find(watcher_.session_id(), caller_);
    json metadata;
    {
      std::lock_guard lock(live->mutex);
      find_channels(*live);
      metadata = {{"session", live->id}, {"scenario", live->scenario}, {"mode", to_string(live->mode)}, {"seed", std::to_string(live->seed)}};
    }
    std::vector<fg::Channel> advertised;
    for (const FeedChannel& channel : channels_) advertised.push_back(channel.channel);
    return {text(fg::server_info(std::string("hrisim ") + core::version(), {"clientPublish", "services", "time"}, metadata, live->id)),
            text(fg::advertise(advertised)), text(fg::advertise_services(kServices))};
  }

  Response on_message(const WebSocketMessage& message) override {
    try {
      if (message.binary) return on_binary(message.data);
      json body;
      try {
        body = core::parse_bounded_json(message.data, "a text message");
      } catch (const core::Error& e) {
        return error_status(std::string("a text message is a JSON object with an op: ") + e.what());
      }
      if (!body.is_object()) return error_status("a text message is a JSON object with an op");
      const std::string op = body.contains("op") && body["op"].is_string() ? body["op"].get<std::string>() : "";
      if (op == "subscribe") return on_subscribe(body);
      if (op == "unsubscribe") return on_unsubscribe(body);
      if (op == "advertise") return on_client_advertise(body);
      if (op == "unadvertise") return on_client_unadvertise(body);
      return error_status("op '" + op + "' is not served here: subscribe, unsubscribe, advertise (clientPublish) and unadvertise are");
    } catch (const core::Error& e) {
      return error_status(e.what());
    } catch (const json::exception& e) {
      return error_status(std::string("invalid message: ") + e.what());
    }
  }

  std::vector<Response> push_frames(std::uint64_t dropped) override;

 private:
  void find_channels(LiveSession& live);
  Response on_subscribe(const json& body);
  Response on_unsubscribe(const json& body);
  Response on_client_advertise(const json& body);
  Response on_client_unadvertise(const json& body);
  Response on_binary(const std::string& message);
  Response on_publish(const fg::ClientMessage& message);
  Response on_service_call(const fg::ServiceCall& call);
  void add_messages(LiveSession& live, std::uint32_t id, Subscription& subscription, const render::Scene* scene, std::vector<Response>& out);
  void add_camera(LiveSession& live, std::uint32_t id, const FeedChannel& channel, std::vector<Response>& out);

  bool due(const Subscription& subscription, double rate, Clock::time_point now) const {
    // Half a push's period of slack: a channel at a third of the push rate goes every third push.
    return subscription.fresh || std::chrono::duration<double>(now - subscription.last_sent).count() + 0.5 / push_rate() >= 1.0 / rate;
  }
  Response data(std::uint32_t subscription, double time, const json& message) const {
    return binary(fg::message_data(subscription, fg::nanoseconds(time), core::json_text(message)));
  }

  std::shared_ptr<Registry> registry_;
  live::Watcher watcher_;
  Caller caller_;
  std::string subprotocol_;
  StreamSettings settings_;
  // Touched on the connection's strand only.
  std::vector<FeedChannel> channels_;
  std::map<std::string, std::string> velocity_topics_;  ///< topic → the robot it drives
  std::map<std::uint32_t, Subscription> subscriptions_;
  std::map<std::uint32_t, std::string> client_channels_;  ///< a client's channel id → the robot it drives
  bool fixed_scene_wanted_ = true;
  std::uint64_t dropped_seen_ = 0;
  Clock::time_point fixed_scene_sent_{};
};

void FoxgloveSocket::find_channels(LiveSession& live) {
  const sim::Session& session = live.session();
  const auto add = [&](std::string topic, const char* schema, Feed feed, std::string robot, std::string source, double rate) {
    const auto id = static_cast<std::uint32_t>(channels_.size() + 1);
    channels_.push_back({{id, std::move(topic), schema}, feed, std::move(robot), std::move(source), rate});
  };
  add("/scene", "foxglove.SceneUpdate", Feed::scene, "", "", settings_.rate);
  add("/tf", "foxglove.FrameTransforms", Feed::transforms, "", "", settings_.rate);
  const auto& agents = session.model().agents;
  for (std::size_t a = 0; a < agents.size(); ++a) {
    const sim::RobotRuntime* runtime = agents[a].kind == scenario::AgentKind::robot ? session.robot_runtime(session.agent_at(static_cast<int>(a))) : nullptr;
    if (!runtime) continue;
    const std::string& robot = agents[a].id;
    for (const auto& laser : runtime->lasers) add("/" + robot + "/" + laser.mount->name, "foxglove.LaserScan", Feed::laser, robot, laser.mount->name, settings_.rate);
    if (runtime->people_detector) add("/" + robot + "/people", "foxglove.PosesInFrame", Feed::people, robot, "", settings_.rate);
    if (agents[a].robot_model->drive) {
      velocity_topics_.emplace("/" + robot + "/cmd_vel", robot);
      velocity_topics_.emplace("/cmd_vel", robot);  // the first robot that drives
    }
  }
  for (const sim::CameraInfo& camera : sim::cameras_of(session)) {
    add("/camera/" + camera.name, "foxglove.CompressedImage", Feed::camera, "", camera.name, settings_.image_rate);
    if (camera.kind == "rgbd_camera") add("/camera/" + camera.name + "/depth", "foxglove.RawImage", Feed::depth, "", camera.name, settings_.image_rate);
  }
  add("/events", "foxglove.Log", Feed::events, "", "", settings_.rate);
  add("/metrics", "hrisim.Metrics", Feed::metrics, "", "", kMetricsRate);
}

Response FoxgloveSocket::on_subscribe(const json& body) {
  std::vector<std::string> refused;
  for (const json& asked : array_field(body, "subscriptions")) {
    const std::uint32_t id = uint32_field(asked, "id", "subscription"), channel = uint32_field(asked, "channelId", "subscription");
    const bool taken = std::any_of(subscriptions_.begin(), subscriptions_.end(), [&](const auto& s) { return channels_[s.second.channel].channel.id == channel; });
    if (channel == 0 || channel > channels_.size()) {
      refused.push_back("no channel " + std::to_string(channel));
    } else if (subscriptions_.contains(id)) {
      refused.push_back("subscription id " + std::to_string(id) + " is in use");
    } else if (taken) {
      refused.push_back("channel " + std::to_string(channel) + " is subscribed already");
    } else {
      subscriptions_.emplace(id, Subscription{channel - 1});
      if (channels_[channel - 1].feed == Feed::scene) fixed_scene_wanted_ = true;
    }
  }
  return refused.empty() ? Response::nothing() : error_status("subscribe: " + core::join(refused, "; "));
}

Response FoxgloveSocket::on_unsubscribe(const json& body) {
  std::vector<std::string> unknown;
  for (const json& id : array_field(body, "subscriptionIds")) {
    if (!id.is_number_unsigned() || subscriptions_.erase(id.get<std::uint64_t>()) == 0) unknown.push_back(id.dump());
  }
  return unknown.empty() ? Response::nothing() : text(fg::status(fg::Level::warning, "unsubscribe: no subscription " + core::join(unknown)));
}

Response FoxgloveSocket::on_client_advertise(const json& body) {
  if (caller_.read_only) return error_status("advertise: this socket's token may only read");
  std::vector<std::string> refused;
  for (const json& channel : array_field(body, "channels")) {
    const std::uint32_t id = uint32_field(channel, "id", "channel");
    const std::string topic = channel.value("topic", ""), encoding = channel.value("encoding", "");
    const auto robot = velocity_topics_.find(topic);
    if (robot == velocity_topics_.end()) {
      std::vector<std::string> topics;
      for (const auto& [known, driven] : velocity_topics_) topics.push_back(known);
      refused.push_back("topic '" + topic + "' drives nothing here" + (topics.empty() ? " (no robot with a drive)" : "; publish a Twist on " + core::join(topics, " or ")));
    } else if (encoding != "json") {
      refused.push_back("channel " + std::to_string(id) + ": encoding '" + encoding + "' is not supported (json is)");
    } else if (client_channels_.size() >= kMaxClientChannels && !client_channels_.contains(id)) {
      refused.push_back("channel " + std::to_string(id) + ": at most " + std::to_string(kMaxClientChannels) + " channels a client");
    } else {
      client_channels_[id] = robot->second;
    }
  }
  return refused.empty() ? Response::nothing() : error_status("advertise: " + core::join(refused, "; "));
}

Response FoxgloveSocket::on_client_unadvertise(const json& body) {
  for (const json& id : array_field(body, "channelIds")) {
    if (id.is_number_unsigned()) client_channels_.erase(id.get<std::uint64_t>());
  }
  return Response::nothing();
}

Response FoxgloveSocket::on_binary(const std::string& message) {
  switch (fg::opcode_of(message)) {
    case fg::kClientMessageData:
      return on_publish(fg::read_client_message(message));
    case fg::kServiceCallRequest:
      return on_service_call(fg::read_service_call(message));
    default:
      return error_status("binary opcode " + std::to_string(fg::opcode_of(message)) + " is not a client message (1: message data, 2: service call)");
  }
}

Response FoxgloveSocket::on_publish(const fg::ClientMessage& message) {
  const auto channel = client_channels_.find(message.channel);
  if (channel == client_channels_.end()) return error_status("message data on channel " + std::to_string(message.channel) + ", which this client has not advertised");
  const json commands = velocity_command(channel->second, message.payload);
  return locked(registry_->find(watcher_.session_id(), caller_), [commands](LiveSession& live) {
    try {
      give_commands(live, commands);
      return Response::nothing();
    } catch (const core::Error& e) {
      return error_status(std::string("velocity not given: ") + e.what());
    }
  });
}

Response FoxgloveSocket::on_service_call(const fg::ServiceCall& call) {
  const auto failure = [service = call.service, id = call.call](const std::string& why) { return text(fg::service_call_failure(service, id, why)); };
  if (call.service < kStep || call.service > kSeek) return failure("no service " + std::to_string(call.service));
  if (call.encoding != "json") return failure("encoding '" + call.encoding + "' is not supported (json is)");
  if (caller_.read_only) return failure("this socket's token may only read");
  json request = json::object();
  try {
    if (!call.payload.empty()) request = core::parse_bounded_json(call.payload, "the request");
  } catch (const core::Error& e) {
    return failure(e.what());
  }
  if (!request.is_object()) return failure("the request is not a JSON object");
  const auto live = registry_->find(watcher_.session_id(), caller_);
  // Each answers with the session's status; a failure, with what went wrong.
  const auto answer = [service = call.service, id = call.call, failure](const std::function<json()>& work) {
    try {
      return binary(fg::service_call_response(service, id, "json", core::json_text(work())));
    } catch (const core::Error& e) {
      return failure(e.what());
    } catch (const json::exception& e) {
      return failure(std::string("invalid request: ") + e.what());
    }
  };
  if (call.service == kSeek) {
    if (!request.contains("tick") || !request["tick"].is_number_integer()) return failure("seek: {\"tick\": an integer} is needed");
    std::shared_ptr<void> place;
    try {
      place = registry_->admit_simulation(caller_.owner);
    } catch (const core::Error& e) {
      return failure(e.what());
    }
    return simulation_later(std::move(place), [live, request, answer] {
      return answer([&] {
        std::lock_guard lock(live->mutex);
        return seek_session(*live, request);
      });
    });
  }
  if (call.service == kStep) {
    const json steps = request.value("n", json(1));
    if (!steps.is_number_integer() || steps.get<std::int64_t>() < 1 || steps.get<std::int64_t>() > kMaxStepsPerRequest) {
      return failure("step: n is an integer from 1 to " + std::to_string(kMaxStepsPerRequest));
    }
    return Response::later([live, steps = steps.get<std::int64_t>(), answer] {
      return answer([&] {
        std::lock_guard lock(live->mutex);
        check_lockstep(*live);
        return json::parse(step_session(*live, steps, std::nullopt));
      });
    });
  }
  return Response::later([live, seed = request.value("seed", json()), answer] {
    return answer([&] {
      std::lock_guard lock(live->mutex);
      return reset_session(*live, seed, json::object());
    });
  });
}

std::vector<Response> FoxgloveSocket::push_frames(std::uint64_t dropped) {
  std::vector<Response> out;
  const auto now = Clock::now();
  if (dropped != dropped_seen_ && std::chrono::duration<double>(now - fixed_scene_sent_).count() >= kFixedSceneResend) {
    dropped_seen_ = dropped;
    fixed_scene_wanted_ = true;  // the push dropped may have held it
  }
  const auto show = [&](LiveSession& live, bool restarted, std::span<const sim::Event> events) {
    if (restarted) fixed_scene_wanted_ = true;
    out.push_back(binary(fg::time_message(fg::nanoseconds(live.session().time()))));
    // The scene is taken once for every channel that draws from it.
    const bool scene_wanted = std::any_of(subscriptions_.begin(), subscriptions_.end(), [&](const auto& s) {
      return channels_[s.second.channel].feed == Feed::scene && due(s.second, channels_[s.second.channel].rate, now);
    });
    const render::Scene scene = scene_wanted ? sim::scene_of(live.session()) : render::Scene{};
    for (auto& [id, subscription] : subscriptions_) {
      const FeedChannel& channel = channels_[subscription.channel];
      if (channel.feed == Feed::events) {
        for (const sim::Event& event : events) out.push_back(data(id, live.session().time(), fg::log_line(event_json(event))));
      }
      if (due(subscription, channel.rate, now)) add_messages(live, id, subscription, &scene, out);
    }
  };
  const live::Watcher::Outcome outcome = watcher_.show_news([&](const live::Watcher::News& news) { show(news.session, news.restarted, news.events); });
  const bool fresh = std::any_of(subscriptions_.begin(), subscriptions_.end(), [](const auto& s) { return s.second.fresh; });
  if (outcome == live::Watcher::Outcome::unchanged && fresh) {
    // Nothing happened, but a new subscription is owed what is there now.
    if (const auto live = registry_->find_if_live(watcher_.session_id())) {
      std::unique_lock lock(live->mutex, std::try_to_lock);
      if (lock) show(*live, false, {});
    }
  }
  return out;
}

void FoxgloveSocket::add_messages(LiveSession& live, std::uint32_t id, Subscription& subscription, const render::Scene* scene, std::vector<Response>& out) {
  const FeedChannel& channel = channels_[subscription.channel];
  const sim::Session& session = live.session();
  const double time = session.time();
  const auto sent = [&] {
    subscription.fresh = false;
    subscription.last_sent = Clock::now();
  };
  const sim::RobotRuntime* runtime = channel.robot.empty() ? nullptr : session.robot_runtime(session.agent_id(channel.robot));
  switch (channel.feed) {
    case Feed::scene:
      if (fixed_scene_wanted_) {
        out.push_back(data(id, time, fg::scene_update(*scene, session, true)));
        fixed_scene_wanted_ = false;
        fixed_scene_sent_ = Clock::now();
      }
      out.push_back(data(id, time, fg::scene_update(*scene, session, false, kMovingLifetime * (1.0 / channel.rate))));
      return sent();
    case Feed::transforms:
      out.push_back(data(id, time, fg::frame_transforms(session)));
      return sent();
    case Feed::laser:
      if (!runtime) return;
      for (const auto& laser : runtime->lasers) {
        if (laser.mount->name != channel.source || laser.reading.tick < 0 || laser.reading.tick == subscription.last_reading) continue;
        out.push_back(data(id, time, fg::laser_scan(laser.reading, session.model().dt)));
        subscription.last_reading = laser.reading.tick;
        sent();
      }
      return;
    case Feed::people:
      if (!runtime || runtime->people.tick < 0 || runtime->people.tick == subscription.last_reading) return;
      out.push_back(data(id, time, fg::people_poses(runtime->people, session.model().dt)));
      subscription.last_reading = runtime->people.tick;
      return sent();
    case Feed::camera:
    case Feed::depth:
      add_camera(live, id, channel, out);
      return sent();
    case Feed::events:
      return sent();  // sent as they come, with each push's news
    case Feed::metrics: {
      const json metrics = metrics_so_far(live);
      out.push_back(data(id, time, {{"tick", metrics["tick"]}, {"time", metrics["time"]}, {"metrics", metrics["metrics"]}}));
      return sent();
    }
  }
}

/// The camera's image (or its depth), drawn on the worker pool from the scene taken now; a camera gone
/// (its robot left) sends nothing.
void FoxgloveSocket::add_camera(LiveSession& live, std::uint32_t id, const FeedChannel& channel, std::vector<Response>& out) {
  try {
    auto draw = draw_later(live.session(), channel.source, settings_.image_width, settings_.image_height);
    const bool depth = channel.feed == Feed::depth;
    out.push_back(Response::later([id, time = live.session().time(), draw = std::move(draw), frame = camera_frame(channel.source), depth] {
      const render::Frame drawn = draw();
      const json image = depth ? fg::depth_image(drawn.depth, drawn.colour.width, drawn.colour.height, frame, time)
                               : fg::compressed_image(render::encode_jpeg(drawn.colour), "jpeg", frame, time);
      return binary(fg::message_data(id, fg::nanoseconds(time), core::json_text(image)));
    }));
  } catch (const core::Error&) {
  }
}

StreamSettings settings_of(const Request& upgrade) {
  StreamSettings settings;
  settings.rate = static_cast<double>(integer_query(upgrade, "rate", 1, static_cast<std::int64_t>(kMaxPushRate), 30));
  settings.image_rate = static_cast<double>(integer_query(upgrade, "image_rate", 1, static_cast<std::int64_t>(kMaxPushRate), 10));
  settings.image_width = static_cast<int>(integer_query(upgrade, "image_width", 16, kMaxFrameSize, 0));
  settings.image_height = static_cast<int>(integer_query(upgrade, "image_height", 16, kMaxFrameSize, 0));
  return settings;
}

}  // namespace

std::shared_ptr<WebSocketPeer> open_foxglove_socket(std::shared_ptr<Registry> registry, const std::shared_ptr<LiveSession>& live, const Request& upgrade) {
  std::string subprotocol = agree_subprotocol(upgrade, fg::kSubprotocols);
  return std::make_shared<FoxgloveSocket>(std::move(registry), live, upgrade.caller, std::move(subprotocol), settings_of(upgrade));
}

}  // namespace hrisim::http
