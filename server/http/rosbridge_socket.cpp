#include "http/rosbridge_socket.hpp"

#include <algorithm>
#include <map>
#include <span>

#include "core/bounded_json.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "http/request_helpers.hpp"
#include "http/robot_frames.hpp"
#include "http/ros_messages.hpp"
#include "http/ros_topics.hpp"
#include "http/rosbridge_graph.hpp"
#include "http/rosbridge_protocol.hpp"
#include "http/session_inputs.hpp"
#include "http/session_limits.hpp"
#include "http/session_views.hpp"
#include "live/watcher.hpp"
#include "render/image_codec.hpp"
#include "sim/session.hpp"

namespace hrisim::http {
namespace {

using nlohmann::json;
namespace rb = rosbridge;

/// How fast a socket streams, from its upgrade's query.
struct StreamSettings {
  double rate = 30.0;        ///< pushes per second: a topic's messages at most this often
  double image_rate = 10.0;  ///< each subscribed camera's images per second at most
};

Response text(const json& message) { return Response{200, "application/json", rb::json_text(message), {}, {}}; }

/// One topic subscribed, however many subscriptions (ids) the client holds on it: sent at the
/// smallest throttle of them, in the compression asked last.
struct Subscription {
  const rb::Topic* topic = nullptr;
  std::map<std::string, double> throttles;  ///< the subscribe ops' ids (as JSON text, "" for none) → seconds between messages at least
  rb::Compression compression = rb::Compression::none;
  Clock::time_point last_sent{};
  std::int64_t last_reading = -1;  ///< the laser's or odometry's tick last sent
  json static_sent;                ///< the sensors' transforms last sent (on /tf_static)
  bool fresh = true;               ///< not served yet: what there is now goes with the next push
  double throttle() const {
    double least = 1e9;
    for (const auto& [id, seconds] : throttles) least = std::min(least, seconds);
    return throttles.empty() ? 0.0 : least;
  }
};

/// An optional non-negative integer field, or `fallback`.
std::int64_t count_field(const json& body, const char* key, std::int64_t fallback) {
  if (!body.contains(key) || body[key].is_null()) return fallback;
  if (!body[key].is_number_integer() || body[key].get<std::int64_t>() < 0) {
    throw core::Error(core::ErrorCode::bad_request, std::string(key) + " must be an integer of at least 0");
  }
  return body[key].get<std::int64_t>();
}

/// A service request from a call's args: an object, a list in the request's field order, or none.
json request_of(const rb::Service& service, const json& args) {
  if (args.is_null()) return json::object();
  if (args.is_object()) return args;
  if (!args.is_array() || args.size() > service.request_fields.size()) {
    throw core::Error(core::ErrorCode::bad_request, "args of " + service.name + " must be an object (or a list of " + std::to_string(service.request_fields.size()) + ")");
  }
  json request = json::object();
  for (std::size_t i = 0; i < args.size(); ++i) request[service.request_fields[i]] = args[i];
  return request;
}

/// What a push sends: messages taken from the session while it is locked and written (completed,
/// encoded) once it is not, so the session waits only for the taking; camera images drawn on the
/// worker pool.
struct Outbox {
  struct Message {
    const rb::Topic* topic;
    rb::Compression compression;
    json message;
    double time;
  };
  std::vector<Message> messages;
  std::vector<Response> drawn;
  void add(const Subscription& subscription, json message, double time) {
    messages.push_back({subscription.topic, subscription.compression, std::move(message), time});
  }
  std::vector<Response> written() && {
    for (const Message& m : messages) drawn.push_back(rb::publish(m.topic->name, m.topic->type, m.message, m.compression, m.time));
    return std::move(drawn);
  }
};

class RosbridgeSocket : public WebSocketPeer {
 public:
  RosbridgeSocket(std::shared_ptr<Registry> registry, const std::shared_ptr<LiveSession>& live, Caller caller, StreamSettings settings)
      : registry_(registry), watcher_(std::move(registry), *live), caller_(std::move(caller)), settings_(settings) {}

  std::string close_reason() const override { return watcher_.session_live() ? "" : "session " + watcher_.session_id() + " ended"; }
  double push_rate() const override { return settings_.rate; }

  std::vector<Response> on_open() override {
    // A session deleted since the upgrade leaves the graph empty; the socket then closes as it ended.
    if (const auto live = registry_->find_if_live(watcher_.session_id())) {
      std::lock_guard lock(live->mutex);
      graph_ = rb::graph_of(live->session());
    }
    return {};
  }

  Response on_message(const WebSocketMessage& message) override {
    json id;
    try {
      if (message.binary) return text(rb::status("error", "binary messages are not read here: send each op as JSON text"));
      json body;
      try {
        body = core::parse_bounded_json(message.data, "a message");  // nesting checked first: never the stack's end
      } catch (const core::Error& e) {
        return text(rb::status("error", std::string("a message is a JSON object with an op: ") + e.what()));
      }
      if (!body.is_object()) return text(rb::status("error", "a message is a JSON object with an op"));
      id = body.value("id", json());
      const std::string op = body.contains("op") && body["op"].is_string() ? body["op"].get<std::string>() : "";
      if (op == "subscribe") return on_subscribe(body);
      if (op == "unsubscribe") return on_unsubscribe(body);
      if (op == "advertise") return on_advertise(body);
      if (op == "unadvertise") return on_unadvertise(body);
      if (op == "publish") return on_publish(body);
      if (op == "call_service") return on_call_service(body);
      if (op == "set_level") return Response::nothing();  // only errors and warnings are sent
      return text(rb::status("error", "op '" + op + "' is not served here: subscribe, unsubscribe, advertise, unadvertise, publish and call_service are", id));
    } catch (const core::Error& e) {
      return text(rb::status("error", e.what(), id));
    } catch (const json::exception& e) {
      return text(rb::status("error", std::string("invalid message: ") + e.what(), id));
    }
  }

  std::vector<Response> push_frames(std::uint64_t dropped) override;

 private:
  Response on_subscribe(const json& body);
  Response on_unsubscribe(const json& body);
  Response on_advertise(const json& body);
  Response on_unadvertise(const json& body);
  Response on_publish(const json& body);
  Response on_call_service(const json& body);
  Response call_on_session(const rb::Service& service, const json& request, const json& id);
  void show(LiveSession& live, bool restarted, std::span<const sim::Event> events, Outbox& out);
  void add_message(LiveSession& live, Subscription& subscription, Outbox& out);
  void add_camera(LiveSession& live, Subscription& subscription, Outbox& out);

  /// The robot a velocity topic drives; core::Error(bad_request) naming the topics that do.
  const std::string& robot_driven_by(const std::string& topic) const {
    const auto found = graph_.velocity_topics.find(topic);
    if (found != graph_.velocity_topics.end()) return found->second;
    std::vector<std::string> topics;
    for (const auto& [name, robot] : graph_.velocity_topics) topics.push_back(name);
    throw core::Error(core::ErrorCode::bad_request, "topic " + topic + " takes nothing here" +
                                                        (topics.empty() ? " (no robot with a drive)" : "; publish a Twist on " + core::join(topics, " or ")));
  }
  bool due(const Subscription& subscription, Clock::time_point now) const {
    double interval = subscription.throttle();
    if (subscription.topic->feed == rb::Feed::camera) interval = std::max(interval, 1.0 / settings_.image_rate);
    // Half a push's period of slack: a throttle of a third of the push period goes every third push.
    return subscription.fresh || std::chrono::duration<double>(now - subscription.last_sent).count() + 0.5 / settings_.rate >= interval;
  }

  std::shared_ptr<Registry> registry_;
  live::Watcher watcher_;
  Caller caller_;
  StreamSettings settings_;
  // Touched on the connection's strand only.
  rb::Graph graph_;
  std::map<std::string, Subscription> subscriptions_;  ///< by topic
  std::map<std::string, std::string> advertised_;      ///< the client's topics → their types
};

Response RosbridgeSocket::on_subscribe(const json& body) {
  const std::string topic = rb::absolute_name(rb::string_field(body, "topic"));
  const rb::Topic* found = graph_.find(topic);
  if (!found) {
    if (graph_.velocity_topics.contains(topic)) throw core::Error(core::ErrorCode::bad_request, "topic " + topic + " is one hrisim takes (publish on it), not one it publishes");
    throw core::Error(core::ErrorCode::not_found, "no topic " + topic + " here: /rosapi/topics lists them");
  }
  if (body.contains("type") && !body["type"].is_null() && ros::canonical_type(body.value("type", "")) != found->type) {
    throw core::Error(core::ErrorCode::bad_request, "topic " + topic + " is " + found->type + ", not " + core::json_text(body["type"]));
  }
  const std::string compression_name = body.contains("compression") && !body["compression"].is_null() ? rb::string_field(body, "compression") : "none";
  const auto compression = rb::compression_named(compression_name);
  const double throttle = static_cast<double>(count_field(body, "throttle_rate", 0)) / 1000.0;
  count_field(body, "queue_length", 0);  // checked; a slow reader loses old messages instead of queueing
  Subscription& subscription = subscriptions_[topic];
  subscription.topic = found;
  const std::string id = body.value("id", json()).is_null() ? "" : core::json_text(body["id"]);
  subscription.throttles[id] = throttle;
  subscription.compression = compression.value_or(rb::Compression::none);
  // A new subscriber is owed what is there now, even what was sent to the last one.
  subscription.fresh = true;
  subscription.last_reading = -1;
  subscription.static_sent = nullptr;
  if (!compression) return text(rb::status("warning", "compression '" + compression_name + "' is not supported (none, cbor and cbor-raw are): sending " + topic + " uncompressed", body.value("id", json())));
  return Response::nothing();
}

Response RosbridgeSocket::on_unsubscribe(const json& body) {
  const std::string topic = rb::absolute_name(rb::string_field(body, "topic"));
  const auto subscription = subscriptions_.find(topic);
  if (subscription == subscriptions_.end()) return text(rb::status("warning", "unsubscribe: " + topic + " is not subscribed", body.value("id", json())));
  // With an id, that subscription ends; without, all of them on the topic.
  const json id = body.value("id", json());
  if (!id.is_null() && subscription->second.throttles.erase(core::json_text(id)) == 0) {
    return text(rb::status("warning", "unsubscribe: no subscription " + core::json_text(id) + " to " + topic, id));
  }
  if (id.is_null() || subscription->second.throttles.empty()) subscriptions_.erase(subscription);
  return Response::nothing();
}

Response RosbridgeSocket::on_advertise(const json& body) {
  const std::string topic = rb::absolute_name(rb::string_field(body, "topic"));
  const std::string type = ros::canonical_type(rb::string_field(body, "type"));
  if (caller_.read_only) throw core::Error(core::ErrorCode::forbidden, "advertise: this socket's token may only read");
  robot_driven_by(topic);
  if (type != rb::kTwist) throw core::Error(core::ErrorCode::bad_request, "topic " + topic + " is " + rb::kTwist + ", not " + core::json_text(body["type"]));
  advertised_[topic] = type;
  return Response::nothing();
}

Response RosbridgeSocket::on_unadvertise(const json& body) {
  const std::string topic = rb::absolute_name(rb::string_field(body, "topic"));
  if (advertised_.erase(topic) == 0) return text(rb::status("warning", "unadvertise: " + topic + " is not advertised", body.value("id", json())));
  return Response::nothing();
}

Response RosbridgeSocket::on_publish(const json& body) {
  const std::string topic = rb::absolute_name(rb::string_field(body, "topic"));
  if (caller_.read_only) throw core::Error(core::ErrorCode::forbidden, "publish: this socket's token may only read");
  const std::string& robot = robot_driven_by(topic);
  // A Twist as ROS fills one in: the fields left out are 0. A differential drive takes its forward
  // speed and its turn rate.
  const json twist = ros::conform(rb::kTwist, body.contains("msg") ? body["msg"] : json::object());
  const json commands = json::array({{{"robot", robot}, {"velocity", {{"linear", twist["linear"]["x"]}, {"angular", twist["angular"]["z"]}}}}});
  return locked(registry_->find(watcher_.session_id(), caller_), [commands, id = body.value("id", json())](LiveSession& live) {
    try {
      give_commands(live, commands);
      return Response::nothing();
    } catch (const core::Error& e) {
      return text(rb::status("error", std::string("velocity not given: ") + e.what(), id));
    }
  });
}

Response RosbridgeSocket::on_call_service(const json& body) {
  const std::string name = rb::absolute_name(rb::string_field(body, "service"));
  const json id = body.value("id", json());
  const rb::Service* service = rb::find_service(name);
  if (!service) return text(rb::service_response(name, "no service " + name + " here: /rosapi/services lists them", false, id));
  try {
    const json request = request_of(*service, body.value("args", json()));
    if (auto answer = rb::introspect(graph_, service->name, request)) return text(rb::service_response(name, *answer, true, id));
    return call_on_session(*service, request, id);
  } catch (const core::Error& e) {
    return text(rb::service_response(name, e.what(), false, id));
  }
}

/// The services that read or change the session: the time, reset, step, seek; each answered on the
/// worker pool when it simulates.
Response RosbridgeSocket::call_on_session(const rb::Service& service, const json& request, const json& id) {
  const auto live = registry_->find(watcher_.session_id(), caller_);
  // Each answers with its values, or (a core::Error) with what went wrong.
  const auto answer = [name = service.name, id](const std::function<json()>& work) {
    try {
      return text(rb::service_response(name, work(), true, id));
    } catch (const core::Error& e) {
      return text(rb::service_response(name, e.what(), false, id));
    }
  };
  const auto done = [](const json& status) {
    return json{{"success", true}, {"message", "tick " + core::json_text(status["tick"])}, {"tick", status["tick"]}, {"time", status["time"]}};
  };
  if (service.name == "/rosapi/get_time") {
    return locked(live, [answer](LiveSession& session) { return answer([&] { return json{{"time", ros::time_of(session.session().time())}}; }); });
  }
  if (caller_.read_only) throw core::Error(core::ErrorCode::forbidden, "this socket's token may only read");
  if (service.name == "/hrisim/reset") {
    return Response::later([live, answer] {
      return answer([&] {
        std::lock_guard lock(live->mutex);
        reset_session(*live, nullptr, json::object());
        return json{{"success", true}, {"message", "reset to tick 0 with seed " + std::to_string(live->seed)}};
      });
    });
  }
  if (service.name == "/hrisim/step") {
    const json steps = request.value("n", json(1));
    if (!steps.is_number_integer() || steps.get<std::int64_t>() < 1 || steps.get<std::int64_t>() > kMaxStepsPerRequest) {
      throw core::Error(core::ErrorCode::bad_request, "n is an integer from 1 to " + std::to_string(kMaxStepsPerRequest));
    }
    return Response::later([live, steps = steps.get<std::int64_t>(), answer, done] {
      return answer([&] {
        std::lock_guard lock(live->mutex);
        check_lockstep(*live);
        return done(json::parse(step_session(*live, steps, std::nullopt)));
      });
    });
  }
  // Seeking simulates again: one of an owner's at a time.
  if (!request.contains("tick") || !request["tick"].is_number_integer()) throw core::Error(core::ErrorCode::bad_request, "tick must be an integer");
  return simulation_later(registry_->admit_simulation(caller_.owner), [live, request, answer, done] {
    return answer([&] {
      std::lock_guard lock(live->mutex);
      return done(seek_session(*live, {{"tick", request["tick"]}}));
    });
  });
}

std::vector<Response> RosbridgeSocket::push_frames(std::uint64_t) {
  Outbox out;
  const live::Watcher::Outcome outcome =
      watcher_.show_news([&](const live::Watcher::News& news) { show(news.session, news.restarted, news.events, out); });
  const bool fresh = std::any_of(subscriptions_.begin(), subscriptions_.end(), [](const auto& s) { return s.second.fresh; });
  if (outcome == live::Watcher::Outcome::unchanged && fresh) {
    // Nothing happened, but a new subscription is owed what is there now.
    if (const auto live = registry_->find_if_live(watcher_.session_id())) {
      std::unique_lock lock(live->mutex, std::try_to_lock);
      if (lock) show(*live, false, {}, out);
    }
  }
  return std::move(out).written();
}

void RosbridgeSocket::show(LiveSession& live, bool restarted, std::span<const sim::Event> events, Outbox& out) {
  const auto now = Clock::now();
  for (auto& [topic, subscription] : subscriptions_) {
    if (restarted) {
      subscription.last_reading = -1;
      subscription.static_sent = nullptr;
    }
    if (subscription.topic->feed == rb::Feed::log) {
      // Every event as it comes: a log line is never throttled away.
      for (const sim::Event& event : events) out.add(subscription, ros::log_line(event_json(event)), live.session().time());
      subscription.fresh = false;
    } else if (due(subscription, now)) {
      add_message(live, subscription, out);
      subscription.fresh = false;  // served what there is (a laser may have no reading yet)
    }
  }
}

void RosbridgeSocket::add_message(LiveSession& live, Subscription& subscription, Outbox& out) {
  const sim::Session& session = live.session();
  const double time = session.time();
  const rb::Topic& topic = *subscription.topic;
  const auto send = [&](json message) {
    out.add(subscription, std::move(message), time);
    subscription.last_sent = Clock::now();
  };
  const sim::RobotRuntime* runtime = topic.robot.empty() ? nullptr : session.robot_runtime(session.agent_id(topic.robot));
  switch (topic.feed) {
    case rb::Feed::clock:
      return send(ros::clock(time));
    case rb::Feed::transforms:
      return send(ros::transforms(session, false));
    case rb::Feed::static_transforms: {
      // Latched: sent again only when a sensor moved on its robot (a head turned), or after a reset.
      json message = ros::transforms(session, true);
      json placed = json::array();
      for (const json& transform : message["transforms"]) placed.push_back(transform["transform"]);
      if (placed == subscription.static_sent) return;
      subscription.static_sent = std::move(placed);
      return send(message);
    }
    case rb::Feed::laser:
      if (!runtime) return;
      for (const auto& laser : runtime->lasers) {
        if (laser.mount->name != topic.source || laser.reading.tick < 0 || laser.reading.tick == subscription.last_reading) continue;
        send(ros::laser_scan(laser.reading, session.model().dt, sensor_frame(topic.robot, topic.source)));
        subscription.last_reading = laser.reading.tick;
      }
      return;
    case rb::Feed::odometry:
      if (!runtime || runtime->odometry_reading.tick < 0 || runtime->odometry_reading.tick == subscription.last_reading) return;
      subscription.last_reading = runtime->odometry_reading.tick;
      return send(ros::odometry(runtime->odometry_reading, session.model().dt, topic.robot));
    case rb::Feed::people:
      return send(ros::people_markers(session));
    case rb::Feed::detections:
      if (!runtime || runtime->people.tick < 0 || runtime->people.tick == subscription.last_reading) return;
      subscription.last_reading = runtime->people.tick;
      return send(ros::people_detected(session, runtime->people));
    case rb::Feed::camera:
      return add_camera(live, subscription, out);
    case rb::Feed::log:
      return;
  }
}

/// The camera's JPEG image, drawn on the worker pool from the scene taken now; a camera gone (its
/// robot left) sends nothing.
void RosbridgeSocket::add_camera(LiveSession& live, Subscription& subscription, Outbox& out) {
  try {
    const rb::Topic& topic = *subscription.topic;
    // The work may outlive the socket: it holds its own copies.
    out.drawn.push_back(Response::later([draw = draw_later(live.session(), topic.source, 0, 0), name = topic.name, type = topic.type,
                                   frame = camera_frame(topic.source), compression = subscription.compression, time = live.session().time()] {
      return rb::publish(name, type, ros::compressed_image(render::encode_jpeg(draw().colour), "jpeg", frame, time), compression, time);
    }));
    subscription.last_sent = Clock::now();
  } catch (const core::Error&) {
  }
}

StreamSettings settings_of(const Request& upgrade) {
  StreamSettings settings;
  settings.rate = static_cast<double>(integer_query(upgrade, "rate", 1, static_cast<std::int64_t>(kMaxPushRate), 30));
  settings.image_rate = static_cast<double>(integer_query(upgrade, "image_rate", 1, static_cast<std::int64_t>(kMaxPushRate), 10));
  return settings;
}

}  // namespace

std::shared_ptr<WebSocketPeer> open_rosbridge_socket(std::shared_ptr<Registry> registry, const std::shared_ptr<LiveSession>& live, const Request& upgrade) {
  return std::make_shared<RosbridgeSocket>(std::move(registry), live, upgrade.caller, settings_of(upgrade));
}

}  // namespace hrisim::http
