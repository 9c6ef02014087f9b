#include "http/sessions_api.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/json_schema.hpp"
#include "core/text.hpp"
#include "http/episodes_api.hpp"
#include "http/frames.hpp"
#include "http/session_work.hpp"
#include "http/request_helpers.hpp"
#include "http/session_inputs.hpp"
#include "http/foxglove_socket.hpp"
#include "http/rosbridge_socket.hpp"
#include "http/session_socket.hpp"
#include "http/session_views.hpp"
#include "http/snapshot_files.hpp"
#include "runs/executor.hpp"
#include "runs/spec.hpp"
#include "storage/store.hpp"
#include "sim/camera_scene.hpp"

namespace hrisim::http {

using nlohmann::json;

/// A 503 for too many sessions carries Retry-After, and says how to end one here.
Response refused(const core::Error& error) {
  Response response = Response::error(error.code() != core::ErrorCode::unavailable
                                          ? error
                                          : core::Error(error.code(), std::string(error.what()) + " (DELETE /api/v1/sessions/{id}, or the browser's Sessions page)",
                                                        error.details()));
  if (error.code() == core::ErrorCode::unavailable) response.headers.emplace_back("Retry-After", std::to_string(kSessionRetryAfter));
  return response;
}

/// 201 with the new session's status, or 503 when the server runs its maximum.
Response created(Registry& registry, NewSession request) {
  try {
    const auto live = registry.create(std::move(request));
    std::lock_guard lock(live->mutex);
    Response response = Response::json(201, status_of(*live));
    response.headers.emplace_back("Location", "/api/v1/sessions/" + live->id);
    return response;
  } catch (const core::Error& error) {
    return refused(error);
  }
}

/// Does `work` that simulates again (a restore, a seek, a start from a snapshot file) on the worker pool,
/// holding one of the owner's places (live::Registry::admit_simulation); 503 with Retry-After when they
/// are all taken.
Response simulation_for(Registry& registry, const Caller& caller, std::function<Response()> work) {
  std::shared_ptr<void> place;
  try {
    place = registry.admit_simulation(caller.owner);
  } catch (const core::Error& error) {
    Response response = Response::error(error);
    response.headers.emplace_back("Retry-After", std::to_string(kSimulationRetryAfter));
    return response;
  }
  return simulation_later(std::move(place), std::move(work));
}

/// A session that plays a stored episode again; stepped to its end it reaches the episode's state hash.
NewSession replay_of(storage::Store& store, ScenarioCatalogue& catalogue, const std::string& id, const Caller& caller) {
  const EpisodeReplay episode = replay_of_episode(store, catalogue, id, caller, "/episode");
  NewSession replay;
  replay.scenario = episode.config.value("scenario", episode.episode.scenario_id);
  replay.model = episode.spec.model;
  replay.controller = episode.request.controller;
  replay.seed = static_cast<std::int64_t>(episode.episode.seed);
  replay.owner = caller.owner;
  replay.episode_id = id;
  replay.time_limit = episode.spec.max_time;
  replay.requests = episode.spec.requests;
  replay.scenario_sha256 = episode.scenario_sha256;
  return replay;
}

namespace {

/// The live-session routes over REST, each a named handler (kSessionRoutes). Bodies reach them checked
/// against api/openapi.yaml (Router::follow): what is read here without a check the contract guarantees.
class SessionRoutes {
 public:
  SessionRoutes(std::shared_ptr<ScenarioCatalogue> catalogue, std::shared_ptr<Registry> registry, std::shared_ptr<TicketBook> tickets,
                storage::Store* store)
      : catalogue_(std::move(catalogue)), registry_(std::move(registry)), tickets_(std::move(tickets)), store_(store) {}

  const std::shared_ptr<Registry>& registry() const { return registry_; }

  Response create(const Request& request) const;
  Response list(const Request& request) const;
  Response ws_ticket(const Request& request) const;
  Response status(const Request& request) const;
  Response remove(const Request& request) const;
  Response take_snapshot(const Request& request) const;
  Response list_snapshots(const Request& request) const;
  Response download_snapshot(const Request& request) const;
  Response delete_snapshot(const Request& request) const;
  Response inputs(const Request& request) const;
  Response restore(const Request& request) const { return simulate_again(request, restore_snapshot); }
  Response seek(const Request& request) const { return simulate_again(request, seek_session); }
  Response scene(const Request& request) const;
  Response state(const Request& request) const;
  Response sensors(const Request& request) const;
  Response audio(const Request& request) const;
  Response poses(const Request& request) const;
  Response place_one(const Request& request) const;
  Response reset(const Request& request) const;
  Response commands(const Request& request) const;
  Response step_many(const Request& request) const;
  Response step(const Request& request) const;
  Response metrics(const Request& request) const;
  Response frame(const Request& request) const;
  Response cameras(const Request& request) const;
  Response action_space(const Request& request) const;
  Response observation_space(const Request& request) const;

 private:
  std::shared_ptr<LiveSession> session_of(const Request& request) const { return registry_->find(request.path_params.at("id"), request.caller); }
  /// A restore or a seek: simulating again is work for the pool, one of an owner's at a time.
  Response simulate_again(const Request& request, json (*go)(LiveSession&, const json&)) const;
  Response from_snapshot_file(const Request& request, Mode mode, double factor, std::optional<std::chrono::seconds> unwatched_grace) const;

  std::shared_ptr<ScenarioCatalogue> catalogue_;
  std::shared_ptr<Registry> registry_;
  std::shared_ptr<TicketBook> tickets_;
  storage::Store* store_;
};

constexpr NamedRoute<SessionRoutes> kSessionRoutes[] = {
    {"POST", "/api/v1/sessions", &SessionRoutes::create},
    {"GET", "/api/v1/sessions", &SessionRoutes::list},
    {"POST", "/api/v1/sessions/step", &SessionRoutes::step_many},
    {"GET", "/api/v1/sessions/{id}", &SessionRoutes::status},
    {"DELETE", "/api/v1/sessions/{id}", &SessionRoutes::remove},
    {"POST", "/api/v1/sessions/{id}/ws-ticket", &SessionRoutes::ws_ticket},
    {"POST", "/api/v1/sessions/{id}/snapshots", &SessionRoutes::take_snapshot},
    {"GET", "/api/v1/sessions/{id}/snapshots", &SessionRoutes::list_snapshots},
    {"GET", "/api/v1/sessions/{id}/snapshots/{snapshot}", &SessionRoutes::download_snapshot},
    {"DELETE", "/api/v1/sessions/{id}/snapshots/{snapshot}", &SessionRoutes::delete_snapshot},
    {"GET", "/api/v1/sessions/{id}/inputs", &SessionRoutes::inputs},
    {"POST", "/api/v1/sessions/{id}/restore", &SessionRoutes::restore},
    {"POST", "/api/v1/sessions/{id}/seek", &SessionRoutes::seek},
    {"GET", "/api/v1/sessions/{id}/scene", &SessionRoutes::scene},
    {"GET", "/api/v1/sessions/{id}/state", &SessionRoutes::state},
    {"GET", "/api/v1/sessions/{id}/robots/{robot}/sensors", &SessionRoutes::sensors},
    {"GET", "/api/v1/sessions/{id}/robots/{robot}/audio", &SessionRoutes::audio},
    {"GET", "/api/v1/sessions/{id}/poses", &SessionRoutes::poses},
    {"PUT", "/api/v1/sessions/{id}/poses/{name}", &SessionRoutes::place_one},
    {"POST", "/api/v1/sessions/{id}/reset", &SessionRoutes::reset},
    {"POST", "/api/v1/sessions/{id}/commands", &SessionRoutes::commands},
    {"POST", "/api/v1/sessions/{id}/step", &SessionRoutes::step},
    {"GET", "/api/v1/sessions/{id}/metrics", &SessionRoutes::metrics},
    {"GET", "/api/v1/sessions/{id}/frames/{camera}", &SessionRoutes::frame},
    {"GET", "/api/v1/sessions/{id}/cameras", &SessionRoutes::cameras},
    {"GET", "/api/v1/sessions/{id}/action_space", &SessionRoutes::action_space},
    {"GET", "/api/v1/sessions/{id}/observation_space", &SessionRoutes::observation_space},
};

Response SessionRoutes::create(const Request& request) const {
  const json& body = request.checked_body;
  const Mode mode = parse_mode(body.value("mode", "lockstep")).value();  // the contract takes the two modes only
  const double factor = body.value("realtime_factor", 1.0);
  std::optional<std::chrono::seconds> unwatched_grace;
  if (body.contains("unwatched_grace") && !body["unwatched_grace"].is_null()) unwatched_grace = std::chrono::seconds(body["unwatched_grace"].get<std::int64_t>());
  if (body.contains("snapshot")) return from_snapshot_file(request, mode, factor, unwatched_grace);
  // Compiling an upload and building the session's world (physics, sensors) are work for the pool.
  return Response::later([catalogue = catalogue_, registry = registry_, store = store_, body, mode, factor, unwatched_grace, caller = request.caller] {
    if (body.contains("episode")) {
      NewSession replay = replay_of(*store, *catalogue, body["episode"], caller);
      replay.mode = mode;
      replay.realtime_factor = factor;
      replay.unwatched_grace = unwatched_grace;
      return created(*registry, std::move(replay));
    }
    const std::string scenario = body["scenario"];
    const auto entry = catalogue->find(scenario, caller);
    if (!entry || !entry->source.model) {
      throw core::Error(core::ErrorCode::not_found, "no scenario '" + scenario + "'", {{"pointer", "/scenario"}, {"id", scenario}});
    }
    std::shared_ptr<const scenario::Model> model = entry->source.model;
    std::optional<json> controller;
    if (body.contains("controller") && !body["controller"].is_null()) {
      json errors = json::array();
      controller = runs::effective_controller(entry->source.document, body["controller"]);
      model = runs::with_controller(entry->source.document, *controller, catalogue->options(*entry).load, errors).model;
      runs::throw_if_problems(errors);
    }
    const std::int64_t seed = body.value("seed", std::int64_t{0});
    return created(*registry, {scenario, model, seed, mode, factor, controller, caller.owner, unwatched_grace, "", std::nullopt, {}, entry->content_sha256()});
  });
}

Response SessionRoutes::from_snapshot_file(const Request& request, Mode mode, double factor, std::optional<std::chrono::seconds> unwatched_grace) const {
  read_snapshot_origin(request.checked_body["snapshot"], "/snapshot");  // a file of another version is refused before any work
  return simulation_for(*registry_, request.caller, [catalogue = catalogue_, registry = registry_, file = request.checked_body["snapshot"], mode, factor,
                                                     unwatched_grace, caller = request.caller] {
    NewSession settings;
    settings.mode = mode;
    settings.realtime_factor = factor;
    settings.unwatched_grace = unwatched_grace;
    try {
      const auto live = start_from_snapshot(*registry, *catalogue, caller, file, std::move(settings));
      std::lock_guard lock(live->mutex);
      Response response = Response::json(201, status_of(*live));
      response.headers.emplace_back("Location", "/api/v1/sessions/" + live->id);
      return response;
    } catch (const core::Error& error) {
      if (error.code() != core::ErrorCode::unavailable) throw;
      return refused(error);
    }
  });
}

Response SessionRoutes::list(const Request& request) const {
  // Each session's lock is taken: on the pool, where waiting behind a long step holds no I/O thread.
  return Response::later([registry = registry_, caller = request.caller] {
    json items = json::array();
    const auto now = Clock::now();
    for (const auto& live : registry->all(caller)) {
      std::lock_guard lock(live->mutex);
      json item = status_of(*live);
      item["unused_for"] = std::chrono::duration<double>(now - live->last_used.load()).count();
      items.push_back(std::move(item));
    }
    return Response::json(200, {{"items", items}});
  });
}

Response SessionRoutes::ws_ticket(const Request& request) const {
  const std::string& id = request.path_params.at("id");
  registry_->find(id, request.caller);
  const std::string ticket = tickets_->issue(id, request.caller);
  return Response::json(201, {{"ticket", ticket}, {"expires_in", kTicketLifetime.count()}, {"url", "/api/v1/sessions/" + id + "/ws?ticket=" + ticket}});
}

Response SessionRoutes::status(const Request& request) const {
  return locked(session_of(request), [](LiveSession& live) { return Response::json(200, status_of(live)); });
}

Response SessionRoutes::remove(const Request& request) const {
  registry_->remove(request.path_params.at("id"), request.caller);
  return Response{204, "application/json", "", {}, {}};
}

Response SessionRoutes::take_snapshot(const Request& request) const {
  return locked(session_of(request), [](LiveSession& session) { return Response::json(201, http::take_snapshot(session)); });
}

Response SessionRoutes::list_snapshots(const Request& request) const {
  return locked(session_of(request), [](LiveSession& session) {
    json items = json::array();
    for (const auto& [id, snapshot] : session.snapshots) items.push_back(snapshot_json(id, snapshot));
    return Response::json(200, {{"items", items}, {"max_snapshots", kMaxSnapshots}});
  });
}

Response SessionRoutes::download_snapshot(const Request& request) const {
  return locked(session_of(request), [name = request.path_params.at("snapshot")](LiveSession& session) {
    const auto found = session.snapshots.find(name);
    if (found == session.snapshots.end()) throw core::Error(core::ErrorCode::not_found, "session " + session.id + " has no snapshot '" + name + "'");
    return download(core::json_text(snapshot_file(session, name, found->second)), "application/json",
                    session.scenario + "-" + session.id + "-" + name + ".json");
  });
}

Response SessionRoutes::delete_snapshot(const Request& request) const {
  return locked(session_of(request), [name = request.path_params.at("snapshot")](LiveSession& session) {
    if (session.snapshots.erase(name) == 0) throw core::Error(core::ErrorCode::not_found, "session " + session.id + " has no snapshot '" + name + "'");
    return Response{204, "application/json", "", {}, {}};
  });
}

Response SessionRoutes::inputs(const Request& request) const {
  return locked(session_of(request), [](LiveSession& session) {
    return Response::json(200, {{"tick", session.session().state().tick}, {"items", input_log_json(session.session().model(), session.episode->input_log())}});
  });
}

Response SessionRoutes::simulate_again(const Request& request, json (*go)(LiveSession&, const json&)) const {
  return simulation_for(*registry_, request.caller, [live = session_of(request), body = request.checked_body, go] {
    std::lock_guard lock(live->mutex);
    return Response::json(200, go(*live, body));
  });
}

Response SessionRoutes::scene(const Request& request) const {
  const auto all = query_value(request.query, "all").value_or("false");
  if (all != "true" && all != "false") throw core::Error(core::ErrorCode::bad_request, "all: true or false", {{"parameter", "all"}});
  return locked(session_of(request), [all = all == "true"](LiveSession& live) { return scene_frame(live.session(), all); });
}

Response SessionRoutes::state(const Request& request) const {
  const auto live = session_of(request);
  const auto since = integer_query(request, "events_since", 0, std::numeric_limits<std::int64_t>::max(), 0);
  return locked(live, [since](LiveSession& session) { return Response::json(200, state_of(session, since)); });
}

Response SessionRoutes::sensors(const Request& request) const {
  return locked(session_of(request), [robot = request.path_params.at("robot")](LiveSession& live) { return Response::json(200, sensors_of(live.session(), robot)); });
}

Response SessionRoutes::audio(const Request& request) const {
  return locked(session_of(request), [robot = request.path_params.at("robot")](LiveSession& live) {
    return Response{200, kBinaryContentType, audio_of(live.session(), robot), {}, {}};
  });
}

Response SessionRoutes::poses(const Request& request) const {
  return locked(session_of(request), [](LiveSession& live) { return Response::json(200, poses_of(live.session())); });
}

Response SessionRoutes::place_one(const Request& request) const {
  return locked(session_of(request), [body = request.checked_body, name = request.path_params.at("name")](LiveSession& session) {
    session.episode->give(place(session.session(), name, body, ""));
    return Response::json(200, poses_of(session.session()));
  });
}

Response SessionRoutes::reset(const Request& request) const {
  const auto live = session_of(request);
  const json& body = request.checked_body;
  const json options = body.value("options", json::object());
  if (options.contains("snapshot")) {
    // Back to a moment kept in a file (its own seed, nothing placed anew): simulated again on the pool.
    return simulation_for(*registry_, request.caller, [live, snapshot = options["snapshot"]] {
      std::lock_guard lock(live->mutex);
      return Response::json(200, reset_to_snapshot(*live, snapshot, "/options/snapshot"));
    });
  }
  // A fresh session is built: work for the pool.
  return Response::later([live, seed_given = body.value("seed", json()), poses = options.value("poses", json::object())] {
    std::lock_guard lock(live->mutex);
    return Response::json(200, reset_session(*live, seed_given, poses));
  });
}

Response SessionRoutes::commands(const Request& request) const {
  return locked(session_of(request), [commands = request.checked_body["commands"]](LiveSession& session) {
    return Response::json(200, give_commands(session, commands));
  });
}

Response SessionRoutes::step_many(const Request& request) const { return http::step_many(*registry_, request.caller, request.checked_body); }

Response SessionRoutes::step(const Request& request) const {
  const auto live = session_of(request);
  const json& body = request.checked_body;
  const std::int64_t steps = body.value("n", std::int64_t{1});
  const auto action = action_of(body.value("action", json()));
  check_lockstep(*live);
  // Stepping may take long: on the worker pool, never on an I/O thread.
  return Response::later([live, steps, action] {
    std::lock_guard lock(live->mutex);
    return Response{200, "application/json", step_session(*live, steps, action), {}, {}};
  });
}

Response SessionRoutes::metrics(const Request& request) const {
  // Computed from every step so far, on the worker pool: a long session has many.
  return Response::later([live = session_of(request)] {
    std::lock_guard lock(live->mutex);
    return Response::json(200, metrics_so_far(*live));
  });
}

Response SessionRoutes::frame(const Request& request) const {
  const auto live = session_of(request);
  const FrameRequest asked = frame_request(request);
  // The scene is copied under the session's lock; drawing happens after, on the worker pool.
  return locked(live, [asked, name = request.path_params.at("camera")](LiveSession& session) {
    const sim::CameraInfo info = sim::camera_of(session.session(), name, asked.width, asked.height);
    return Response::later([scene = sim::scene_for(session.session(), info), camera = info.camera, asked] {
      return encode_frame(render::render_on_this_thread(scene, camera), asked);
    });
  });
}

Response SessionRoutes::cameras(const Request& request) const {
  return locked(session_of(request), [](LiveSession& live) {
    json cameras = json::array();
    for (const sim::CameraInfo& info : sim::cameras_of(live.session())) cameras.push_back(camera_json(info));
    return Response::json(200, {{"id", live.id}, {"tick", live.session().state().tick}, {"cameras", cameras}, {"segmentation", segmentation_legend(live.session())}});
  });
}

Response SessionRoutes::action_space(const Request& request) const {
  return locked(session_of(request), [](LiveSession& live) {
    if (!live.environment()) throw core::Error(core::ErrorCode::conflict, "this session has no robot that can act");
    return Response::json(200, space_json(live.environment()->action_space()));
  });
}

Response SessionRoutes::observation_space(const Request& request) const {
  return locked(session_of(request), [](LiveSession& live) {
    if (!live.environment()) throw core::Error(core::ErrorCode::conflict, "this session has no robot to observe");
    return Response::json(200, space_json(live.environment()->observation_space(), live.environment()->image()));
  });
}

}  // namespace

void add_session_routes(Router& router, std::shared_ptr<ScenarioCatalogue> catalogue, SessionLimits limits, std::shared_ptr<TicketBook> tickets,
                        storage::Store* store) {
  const auto routes = std::make_shared<const SessionRoutes>(std::move(catalogue), std::make_shared<Registry>(limits), std::move(tickets), store);
  add_routes(router, routes, kSessionRoutes);
  router.add_websocket("/api/v1/sessions/{id}/ws", [registry = routes->registry()](const Request& request) -> std::shared_ptr<WebSocketPeer> {
    // 404 for an unknown session, before the upgrade; the Origin was checked by the guard.
    return open_session_socket(registry, registry->find(request.path_params.at("id"), request.caller), request.caller);
  });
  router.add_websocket("/api/v1/sessions/{id}/foxglove", [registry = routes->registry()](const Request& request) -> std::shared_ptr<WebSocketPeer> {
    return open_foxglove_socket(registry, registry->find(request.path_params.at("id"), request.caller), request);
  });
  router.add_websocket("/api/v1/sessions/{id}/rosbridge", [registry = routes->registry()](const Request& request) -> std::shared_ptr<WebSocketPeer> {
    return open_rosbridge_socket(registry, registry->find(request.path_params.at("id"), request.caller), request);
  });
}

}  // namespace hrisim::http
