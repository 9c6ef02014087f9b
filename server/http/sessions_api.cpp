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
#include "http/session_socket.hpp"
#include "http/session_views.hpp"
#include "http/snapshot_files.hpp"
#include "metrics/episode_metrics.hpp"
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

void add_session_routes(Router& router, std::shared_ptr<ScenarioCatalogue> catalogue, SessionLimits limits, std::shared_ptr<TicketBook> tickets,
                        storage::Store* store) {
  auto registry = std::make_shared<Registry>(limits);

  router.add("POST", "/api/v1/sessions", [catalogue, registry, store](const Request& request) {
    const json body = json_object_body(request);
    refuse_unknown_keys(body, {"scenario", "episode", "snapshot", "seed", "mode", "realtime_factor", "controller", "unwatched_grace"});
    if (body.contains("snapshot")) {
      for (const char* key : {"scenario", "episode", "seed", "controller"}) {
        if (body.contains(key)) {
          throw core::Error(core::ErrorCode::bad_request, std::string(key) + ": a session started from a snapshot takes the snapshot's own",
                            {{"pointer", std::string("/") + key}});
        }
      }
      read_snapshot_origin(body["snapshot"], "/snapshot");  // a malformed file is refused before any work
    } else if (body.contains("episode")) {
      for (const char* key : {"scenario", "seed", "controller"}) {
        if (body.contains(key)) {
          throw core::Error(core::ErrorCode::bad_request, std::string(key) + ": a replay of an episode takes the episode's own",
                            {{"pointer", std::string("/") + key}});
        }
      }
      if (!body["episode"].is_string()) throw core::Error(core::ErrorCode::bad_request, "episode: the id of a stored episode", {{"pointer", "/episode"}});
    } else if (!body.contains("scenario") || !body["scenario"].is_string()) {
      throw core::Error(core::ErrorCode::bad_request, "scenario: the id of a scenario is required", {{"pointer", "/scenario"}});
    }
    const std::string scenario = body.value("scenario", "");
    const std::int64_t seed = integer_field(body, "seed", 0, kMaxSeed, 0);
    const std::optional<Mode> asked_mode =
        !body.contains("mode") ? Mode::lockstep : body["mode"].is_string() ? parse_mode(body["mode"].get<std::string>()) : std::nullopt;
    if (!asked_mode) throw core::Error(core::ErrorCode::bad_request, "mode: lockstep or realtime", {{"pointer", "/mode"}});
    const Mode mode = *asked_mode;
    double factor = 1.0;
    if (body.contains("realtime_factor")) {
      const json& value = body["realtime_factor"];
      if (mode != Mode::realtime || !value.is_number() || !(value.get<double>() > 0.0) || value.get<double>() > kMaxRealtimeFactor) {
        throw core::Error(core::ErrorCode::bad_request,
                          "realtime_factor: for a realtime session, simulated seconds per second, above 0 and at most " +
                              std::to_string(static_cast<int>(kMaxRealtimeFactor)),
                          {{"pointer", "/realtime_factor"}});
      }
      factor = value.get<double>();
    }
    std::optional<std::chrono::seconds> unwatched_grace;
    if (body.contains("unwatched_grace") && !body["unwatched_grace"].is_null()) {
      unwatched_grace = std::chrono::seconds(integer_field(body, "unwatched_grace", 1, kMaxUnwatchedGrace.count(), 0));
    }
    if (body.contains("snapshot")) {
      return simulation_for(*registry, request.caller, [catalogue, registry, body, mode, factor, unwatched_grace, caller = request.caller] {
        NewSession settings;
        settings.mode = mode;
        settings.realtime_factor = factor;
        settings.unwatched_grace = unwatched_grace;
        try {
          const auto live = start_from_snapshot(*registry, *catalogue, caller, body["snapshot"], std::move(settings));
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
    // Compiling an upload and building the session's world (physics, sensors) are work for the pool.
    return Response::later([catalogue, registry, store, body, scenario, seed, mode, factor, unwatched_grace, caller = request.caller] {
      if (body.contains("episode")) {
        NewSession replay = replay_of(*store, *catalogue, body["episode"], caller);
        replay.mode = mode;
        replay.realtime_factor = factor;
        replay.unwatched_grace = unwatched_grace;
        return created(*registry, std::move(replay));
      }
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
      return created(*registry, {scenario, model, seed, mode, factor, controller, caller.owner, unwatched_grace, "", std::nullopt, {}, entry->content_sha256()});
    });
  });

  router.add("GET", "/api/v1/sessions", [registry](const Request& request) {
    // Each session's lock is taken: on the pool, where waiting behind a long step holds no I/O thread.
    return Response::later([registry, caller = request.caller] {
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
  });

  router.add_websocket("/api/v1/sessions/{id}/ws", [registry](const Request& request) -> std::shared_ptr<WebSocketPeer> {
    // 404 for an unknown session, before the upgrade; the Origin was checked by the guard.
    return open_session_socket(registry, registry->find(request.path_params.at("id"), request.caller), request.caller);
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
    return locked(registry->find(request.path_params.at("id"), request.caller), [](LiveSession& live) { return Response::json(200, status_of(live)); });
  });

  router.add("DELETE", "/api/v1/sessions/{id}", [registry](const Request& request) {
    registry->remove(request.path_params.at("id"), request.caller);
    return Response{204, "application/json", "", {}, {}};
  });

  router.add("POST", "/api/v1/sessions/{id}/snapshots", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    refuse_unknown_keys(json_object_body(request), {});
    return locked(live, [](LiveSession& session) { return Response::json(201, take_snapshot(session)); });
  });

  router.add("GET", "/api/v1/sessions/{id}/snapshots", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    return locked(live, [](LiveSession& session) {
      json items = json::array();
      for (const auto& [id, snapshot] : session.snapshots) items.push_back(snapshot_json(id, snapshot));
      return Response::json(200, {{"items", items}, {"max_snapshots", kMaxSnapshots}});
    });
  });

  router.add("GET", "/api/v1/sessions/{id}/snapshots/{snapshot}", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    return locked(live, [name = request.path_params.at("snapshot")](LiveSession& session) {
      const auto found = session.snapshots.find(name);
      if (found == session.snapshots.end()) throw core::Error(core::ErrorCode::not_found, "session " + session.id + " has no snapshot '" + name + "'");
      return download(core::json_text(snapshot_file(session, name, found->second)), "application/json",
                      session.scenario + "-" + session.id + "-" + name + ".json");
    });
  });

  router.add("GET", "/api/v1/sessions/{id}/inputs", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    return locked(live, [](LiveSession& session) {
      return Response::json(200, {{"tick", session.session().state().tick}, {"items", input_log_json(session.session().model(), session.episode->input_log())}});
    });
  });

  router.add("DELETE", "/api/v1/sessions/{id}/snapshots/{snapshot}", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    return locked(live, [name = request.path_params.at("snapshot")](LiveSession& session) {
      if (session.snapshots.erase(name) == 0) throw core::Error(core::ErrorCode::not_found, "session " + session.id + " has no snapshot '" + name + "'");
      return Response{204, "application/json", "", {}, {}};
    });
  });

  // Restoring a snapshot and seeking simulate again: work for the pool, one of an owner's at a time.
  using GoTo = json (*)(LiveSession&, const json&);
  for (const auto& route : {std::pair<const char*, GoTo>{"/api/v1/sessions/{id}/restore", restore_snapshot},
                            std::pair<const char*, GoTo>{"/api/v1/sessions/{id}/seek", seek_session}}) {
    const GoTo go = route.second;  // a plain variable: lambdas may not capture structured bindings in C++20
    router.add("POST", route.first, [registry, go](const Request& request) {
      const auto live = registry->find(request.path_params.at("id"), request.caller);
      const json body = json_object_body(request);
      return simulation_for(*registry, request.caller, [live, body, go] {
        std::lock_guard lock(live->mutex);
        return Response::json(200, go(*live, body));
      });
    });
  }

  router.add("GET", "/api/v1/sessions/{id}/scene", [registry](const Request& request) {
    const auto all = query_value(request.query, "all").value_or("false");
    if (all != "true" && all != "false") throw core::Error(core::ErrorCode::bad_request, "all: true or false", {{"parameter", "all"}});
    return locked(registry->find(request.path_params.at("id"), request.caller), [all = all == "true"](LiveSession& live) { return scene_frame(live.session(), all); });
  });

  router.add("GET", "/api/v1/sessions/{id}/state", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    const auto since = integer_query(request, "events_since", 0, std::numeric_limits<std::int64_t>::max(), 0);
    return locked(live, [since](LiveSession& session) { return Response::json(200, state_of(session, since)); });
  });

  router.add("GET", "/api/v1/sessions/{id}/robots/{robot}/sensors", [registry](const Request& request) {
    return locked(registry->find(request.path_params.at("id"), request.caller), [robot = request.path_params.at("robot")](LiveSession& live) {
      return Response::json(200, sensors_of(live.session(), robot));
    });
  });

  router.add("GET", "/api/v1/sessions/{id}/robots/{robot}/audio", [registry](const Request& request) {
    return locked(registry->find(request.path_params.at("id"), request.caller), [robot = request.path_params.at("robot")](LiveSession& live) {
      return Response{200, kBinaryContentType, audio_of(live.session(), robot), {}, {}};
    });
  });

  router.add("GET", "/api/v1/sessions/{id}/poses", [registry](const Request& request) {
    return locked(registry->find(request.path_params.at("id"), request.caller), [](LiveSession& live) { return Response::json(200, poses_of(live.session())); });
  });

  router.add("PUT", "/api/v1/sessions/{id}/poses/{name}", [registry](const Request& request) {
    const auto live = registry->find(request.path_params.at("id"), request.caller);
    return locked(live, [body = json_object_body(request), name = request.path_params.at("name")](LiveSession& session) {
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
    refuse_unknown_keys(options, {"poses", "snapshot"}, "/options");
    if (options.contains("snapshot")) {
      // Back to a moment kept in a file: its own seed, nothing placed anew; simulated again on the pool.
      for (const char* key : {"seed", "poses"}) {
        if (body.contains(key) || options.contains(key)) {
          throw core::Error(core::ErrorCode::bad_request, std::string(key) + ": a snapshot brings its own",
                            {{"pointer", body.contains(key) ? std::string("/") + key : std::string("/options/") + key}});
        }
      }
      return simulation_for(*registry, request.caller, [live, snapshot = options["snapshot"]] {
        std::lock_guard lock(live->mutex);
        return Response::json(200, reset_to_snapshot(*live, snapshot, "/options/snapshot"));
      });
    }
    const json poses = options.value("poses", json::object());
    if (!poses.is_object()) throw core::Error(core::ErrorCode::bad_request, "options.poses: {name: pose}", {{"pointer", "/options/poses"}});
    // A fresh session is built: work for the pool.
    return Response::later([live, body, poses] {
      std::lock_guard lock(live->mutex);
      const std::int64_t seed = integer_field(body, "seed", 0, kMaxSeed, live->seed);
      // A fresh episode of the same scenario: everything starts again from tick 0, then the poses given
      // are set (all or none: a bad one leaves the old session as it was).
      std::unique_ptr<episode::Episode> fresh = live->new_episode(live->session().shared_model(), seed);
      for (const auto& [name, pose] : poses.items()) {
        fresh->give(place(fresh->session(), name, pose, "/options/poses/" + core::pointer_token(name)));
      }
      live->seed = seed;
      ++live->generation;
      live->episode = std::move(fresh);
      live->snapshots.clear();
      live->events_reported = 0;
      live->realtime_origin = Clock::now();
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
    return locked(live, [commands = body["commands"]](LiveSession& session) { return Response::json(200, give_commands(session, commands)); });
  });

  router.add("POST", "/api/v1/sessions/step", [registry](const Request& request) {
    return step_many(*registry, request.caller, json_object_body(request));
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
      return Response{200, "application/json", step_session(*live, steps, action), {}, {}};
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
    return locked(live, [asked, name = request.path_params.at("camera")](LiveSession& session) {
      const sim::CameraInfo info = sim::camera_of(session.session(), name, asked.width, asked.height);
      return Response::later([scene = sim::scene_for(session.session(), info), camera = info.camera, asked] {
        return encode_frame(render::render_on_this_thread(scene, camera), asked);
      });
    });
  });

  router.add("GET", "/api/v1/sessions/{id}/cameras", [registry](const Request& request) {
    return locked(registry->find(request.path_params.at("id"), request.caller), [](LiveSession& live) {
      json cameras = json::array();
      for (const sim::CameraInfo& info : sim::cameras_of(live.session())) cameras.push_back(camera_json(info));
      return Response::json(200, {{"id", live.id}, {"tick", live.session().state().tick}, {"cameras", cameras},
                                  {"segmentation", segmentation_legend(live.session())}});
    });
  });

  router.add("GET", "/api/v1/sessions/{id}/action_space", [registry](const Request& request) {
    return locked(registry->find(request.path_params.at("id"), request.caller), [](LiveSession& live) {
      if (!live.environment()) throw core::Error(core::ErrorCode::conflict, "this session has no robot that can act");
      return Response::json(200, space_json(live.environment()->action_space()));
    });
  });

  router.add("GET", "/api/v1/sessions/{id}/observation_space", [registry](const Request& request) {
    return locked(registry->find(request.path_params.at("id"), request.caller), [](LiveSession& live) {
      if (!live.environment()) throw core::Error(core::ErrorCode::conflict, "this session has no robot to observe");
      return Response::json(200, space_json(live.environment()->observation_space(), live.environment()->image()));
    });
  });
}

}  // namespace hrisim::http

