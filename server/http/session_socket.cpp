#include "http/session_socket.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <optional>
#include <string_view>

#include "core/error.hpp"
#include "http/frames.hpp"
#include "http/request_contract.hpp"
#include "http/request_helpers.hpp"
#include "http/session_limits.hpp"
#include "http/session_inputs.hpp"
#include "http/session_views.hpp"
#include "live/watcher.hpp"
#include "sim/camera_scene.hpp"

namespace hrisim::http {
namespace {

using nlohmann::json;

/// A session's WebSocket: each message is answered once, in order, by the handler its type names in
/// kMessageTypes (the messages and answers are in api/asyncapi.yaml, and each message is checked against
/// its schema there before its handler reads it). A wrong message gets
/// {"type": "error", "error": {code, message, details}} and the socket stays open.
class SessionSocket : public WebSocketPeer {
 public:
  /// A message type the socket answers, what answers it, and whether it changes the session (a
  /// read-only token may not send those).
  struct MessageType {
    std::string_view name;
    Response (SessionSocket::*handle)(const std::shared_ptr<LiveSession>&, json&);
    bool changes_session;
  };
  static const std::array<MessageType, 13> kMessageTypes;

  /// Watches the session (live::Watcher): a deleted one is freed, and the socket then closes.
  SessionSocket(std::shared_ptr<Registry> registry, const std::shared_ptr<LiveSession>& live, Caller caller)
      : registry_(registry), watcher_(std::move(registry), *live), caller_(std::move(caller)) {}

  std::string close_reason() const override { return watcher_.session_live() ? "" : "session " + watcher_.session_id() + " ended"; }

  Response on_message(const WebSocketMessage& message) override;

  double push_rate() const override { return rate_; }

  std::vector<Response> push_frames(std::uint64_t dropped) override {
    std::vector<Response> frames;
    const live::Watcher::Outcome outcome = watcher_.show_news([&](const live::Watcher::News& news) {
      json frame = state_of(news.session, std::numeric_limits<std::int64_t>::max());
      json fresh = json::array();
      for (const sim::Event& event : news.events) fresh.push_back(event_json(event));
      frame["events"] = fresh;
      frame["dropped_frames"] = dropped;
      frame["type"] = "state_frame";
      frames.push_back(Response::json(200, frame));
      if (!camera_) return;
      try {
        frames.push_back(camera_frame(news.session.session(), camera_->name, camera_->width, camera_->height, camera_->ids));
      } catch (const core::Error&) {
        camera_.reset();  // the robot carrying it left the session
      }
    });
    if (outcome == live::Watcher::Outcome::gone) rate_ = 0.0;
    return frames;
  }

 private:
  Response on_step(const std::shared_ptr<LiveSession>& live, json& body) {
    const std::int64_t steps = body.value("n", std::int64_t{1});
    const auto action = action_of(body.value("action", json()));
    check_lockstep(*live);
    return Response::later([live, steps, action] {
      try {
        std::lock_guard lock(live->mutex);
        return Response{200, "application/json", step_session(*live, steps, action, "step"), {}, {}};
      } catch (const core::Error& e) {
        return failure(e);
      }
    });
  }

  Response on_step_many(const std::shared_ptr<LiveSession>&, json& body) { return step_many(*registry_, caller_, body, "step_many"); }

  Response on_commands(const std::shared_ptr<LiveSession>& live, json& body) {
    return answer_locked(live, [commands = body["commands"]](LiveSession& session) { return reply("commands", give_commands(session, commands)); });
  }

  Response on_snapshot(const std::shared_ptr<LiveSession>& live, json&) {
    return answer_locked(live, [](LiveSession& session) { return reply("snapshot", take_snapshot(session)); });
  }

  Response on_restore(const std::shared_ptr<LiveSession>& live, json& body) { return simulated_again(live, body, "restore", restore_snapshot); }

  Response on_seek(const std::shared_ptr<LiveSession>& live, json& body) { return simulated_again(live, body, "seek", seek_session); }

  /// Restoring and seeking simulate again: work for the pool, one of an owner's at a time.
  Response simulated_again(const std::shared_ptr<LiveSession>& live, const json& body, const char* type, json (*go)(LiveSession&, const json&)) {
    return simulation_later(registry_->admit_simulation(caller_.owner), [live, body, type, go] {
      try {
        std::lock_guard lock(live->mutex);
        return reply(type, go(*live, body));
      } catch (const core::Error& e) {
        return failure(e);
      }
    });
  }

  Response on_sensors(const std::shared_ptr<LiveSession>& live, json& body) {
    return answer_locked(live, [robot = body["robot"].get<std::string>()](LiveSession& session) { return reply("sensors", sensors_of(session.session(), robot)); });
  }

  Response on_laser(const std::shared_ptr<LiveSession>& live, json& body) {
    return answer_locked(live, [robot = body["robot"].get<std::string>(), sensor = body.value("sensor", "")](LiveSession& session) {
      return Response{200, kBinaryContentType, laser_of(session.session(), robot, sensor), {}, {}};
    });
  }

  Response on_audio(const std::shared_ptr<LiveSession>& live, json& body) {
    return answer_locked(live, [robot = body["robot"].get<std::string>()](LiveSession& session) {
      return Response{200, kBinaryContentType, audio_of(session.session(), robot), {}, {}};
    });
  }

  Response on_camera(const std::shared_ptr<LiveSession>& live, json& body) {
    const int width = body.value("width", 0), height = body.value("height", 0);
    return answer_locked(live, [camera = body["camera"].get<std::string>(), width, height, ids = body.value("ids", false)](LiveSession& session) {
      return camera_frame(session.session(), camera, width, height, ids);
    });
  }

  Response on_scene(const std::shared_ptr<LiveSession>& live, json& body) {
    return answer_locked(live, [all = body.value("all", false)](LiveSession& session) { return scene_frame(session.session(), all); });
  }

  Response on_subscribe(const std::shared_ptr<LiveSession>& live, json& body) {
    std::optional<CameraSubscription> camera;
    if (body.contains("camera") && !body["camera"].is_null()) {
      const json& asked = body["camera"];
      camera = CameraSubscription{asked["name"], asked.value("width", 0), asked.value("height", 0), asked.value("ids", false)};
      // An unknown camera is refused now, unless the session is busy (then the first push drops it).
      if (std::unique_lock lock(live->mutex, std::try_to_lock); lock) sim::camera_of(live->session(), camera->name, camera->width, camera->height);
    }
    rate_ = body["rate"].get<double>();
    camera_ = rate_ > 0.0 ? camera : std::nullopt;  // rate 0 stops both kinds of frame
    json answer = {{"rate", rate_}, {"camera", nullptr}};
    if (camera_) answer["camera"] = {{"name", camera_->name}, {"width", camera_->width}, {"height", camera_->height}, {"ids", camera_->ids}};
    return reply("subscribed", answer);
  }

  Response on_state(const std::shared_ptr<LiveSession>& live, json& body) {
    const std::int64_t since = body.value("events_since", std::int64_t{0});
    return answer_locked(live, [since](LiveSession& session) { return reply("state", state_of(session, since)); });
  }

  /// locked(), with errors answered as WebSocket error messages wherever the work runs.
  static Response answer_locked(std::shared_ptr<LiveSession> live, std::function<Response(LiveSession&)> work) {
    return locked(std::move(live), [work = std::move(work)](LiveSession& session) {
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
  live::Watcher watcher_;
  Caller caller_;
  // Touched on the connection's strand only.
  double rate_ = 0.0;              ///< state frames per second subscribed to
  struct CameraSubscription {
    std::string name;
    int width = 0, height = 0;
    bool ids = false;
  };
  std::optional<CameraSubscription> camera_;  ///< a camera frame follows each state frame
};

const std::array<SessionSocket::MessageType, 13> SessionSocket::kMessageTypes{{
    {"step", &SessionSocket::on_step, true},
    {"step_many", &SessionSocket::on_step_many, true},
    {"commands", &SessionSocket::on_commands, true},
    {"snapshot", &SessionSocket::on_snapshot, true},
    {"restore", &SessionSocket::on_restore, true},
    {"seek", &SessionSocket::on_seek, true},
    {"state", &SessionSocket::on_state, false},
    {"sensors", &SessionSocket::on_sensors, false},
    {"laser", &SessionSocket::on_laser, false},
    {"audio", &SessionSocket::on_audio, false},
    {"camera", &SessionSocket::on_camera, false},
    {"scene", &SessionSocket::on_scene, false},
    {"subscribe", &SessionSocket::on_subscribe, false},
}};

Response SessionSocket::on_message(const WebSocketMessage& message) {
  try {
    if (message.binary) throw core::Error(core::ErrorCode::bad_request, "this socket's messages are JSON text, not binary");
    Request request;
    request.body = message.data;
    json body = json_object_body(request);
    const std::string type = body.contains("type") && body["type"].is_string() ? body["type"].get<std::string>() : "";
    const auto live = registry_->find(watcher_.session_id(), caller_);
    const auto found = std::find_if(kMessageTypes.begin(), kMessageTypes.end(), [&](const MessageType& known) { return known.name == type; });
    if (found == kMessageTypes.end()) {
      std::string names;
      for (const MessageType& known : kMessageTypes) names += (names.empty() ? "" : &known == &kMessageTypes.back() ? " or " : ", ") + std::string(known.name);
      throw core::Error(core::ErrorCode::bad_request, "type must be " + names, {{"pointer", "/type"}});
    }
    if (caller_.read_only && found->changes_session) {
      throw core::Error(core::ErrorCode::forbidden, "this socket's token may only read", {{"pointer", "/type"}});
    }
    const core::JsonSchema* schema = RequestContract::embedded().message(type);
    if (schema == nullptr) throw core::Error(core::ErrorCode::internal, "message " + type + " is not described in api/asyncapi.yaml");
    check_against(*schema, body);
    body.erase("type");
    return (this->*found->handle)(live, body);
  } catch (const core::Error& e) {
    return failure(e);
  } catch (const json::exception& e) {
    return failure(wrong_type(e));
  }
}

}  // namespace

std::shared_ptr<WebSocketPeer> open_session_socket(std::shared_ptr<Registry> registry, const std::shared_ptr<LiveSession>& live, Caller caller) {
  return std::make_shared<SessionSocket>(std::move(registry), live, std::move(caller));
}

}  // namespace hrisim::http
