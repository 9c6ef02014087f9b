#include "http/snapshot_files.hpp"


#include "core/build_info.hpp"
#include "core/error.hpp"
#include "http/request_helpers.hpp"
#include "http/session_inputs.hpp"
#include "http/session_limits.hpp"
#include "runs/spec.hpp"

namespace hrisim::http {

using nlohmann::json;
using Entry = episode::Episode::Snapshot::Entry;

namespace {

[[noreturn]] void malformed(const std::string& at, const std::string& what) { throw core::Error(core::ErrorCode::bad_request, what, {{"pointer", at}}); }

}  // namespace

json input_log_json(const scenario::Model& model, const std::vector<Entry>& log) {
  json entries = json::array();
  for (const Entry& entry : log) {
    json item = entry.kind == Entry::Kind::input ? input_json(model, *entry.input) : json::object();
    item["tick"] = entry.tick;
    if (entry.kind == Entry::Kind::step) {
      item["steps"] = entry.count;
      if (entry.action) item["action"] = *entry.action;
    } else if (entry.kind == Entry::Kind::ticks) {
      item["ticks"] = entry.count;
    }
    entries.push_back(std::move(item));
  }
  return entries;
}

json snapshot_file(const LiveSession& live, const std::string& id, const episode::Episode::Snapshot& snapshot) {
  json file = {{"hrisim_snapshot", kSnapshotFileFormat},
               {"hrisim", {{"version", core::version()}, {"commit", core::git_commit()}}},
               {"snapshot", id},
               {"session", live.id},
               {"scenario", live.scenario},
               {"scenario_sha256", live.scenario_sha256},
               {"seed", live.seed},
               {"tick", snapshot.tick},
               {"state_hash", sim::hash_hex(snapshot.state_hash)},
               {"inputs", input_log_json(live.session().model(), snapshot.log)}};
  if (live.controller) file["controller"] = *live.controller;
  if (live.time_limit) file["time_limit"] = *live.time_limit;
  if (!live.requests.empty()) {
    json requests = json::array();
    for (const auto& [time, routine] : live.requests) requests.push_back({{"time", time}, {"routine", routine}});
    file["requests"] = requests;
  }
  return file;
}

SnapshotOrigin read_snapshot_origin(const json& file, const std::string& at) {
  const std::string version = file["hrisim"]["version"];
  if (version != core::version()) {
    throw core::Error(core::ErrorCode::conflict,
                      "the snapshot was taken by hrisim " + version + "; this server is hrisim " + core::version() +
                          ": a snapshot file starts a session only on a server of the version that took it",
                      {{"pointer", at + "/hrisim/version"}, {"snapshot_version", version}, {"server_version", core::version()}});
  }
  SnapshotOrigin origin;
  origin.scenario = file["scenario"];
  origin.scenario_sha256 = file["scenario_sha256"];
  origin.seed = file["seed"];
  if (file.contains("controller")) origin.controller = file["controller"];
  if (file.contains("time_limit")) origin.time_limit = file["time_limit"].get<double>();
  for (const json& request : file.value("requests", json::array())) origin.requests.emplace_back(request["time"].get<double>(), request["routine"].get<std::string>());
  return origin;
}

episode::Episode::Snapshot read_snapshot_log(const sim::Session& session, const json& file, const std::string& at) {
  episode::Episode::Snapshot snapshot;
  snapshot.tick = file["tick"];
  snapshot.state_hash = std::stoull(file["state_hash"].get<std::string>(), nullptr, 16);
  const json& inputs = file["inputs"];
  std::int64_t last_tick = 0;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const std::string here = at + "/inputs/" + std::to_string(i);
    const json& given = inputs[i];
    Entry entry;
    entry.tick = given["tick"];
    if (entry.tick < last_tick || entry.tick > snapshot.tick) {
      throw core::Error(core::ErrorCode::bad_request,
                        "tick: an input's tick is from the previous input's (" + std::to_string(last_tick) + ") to the snapshot's (" +
                            std::to_string(snapshot.tick) + ")",
                        {{"pointer", here + "/tick"}});
    }
    last_tick = entry.tick;
    if (given.contains("steps")) {
      entry.kind = Entry::Kind::step;
      entry.count = given["steps"];
      entry.action = action_of(given.value("action", json()));
    } else if (given.contains("ticks")) {
      entry.kind = Entry::Kind::ticks;
      entry.count = given["ticks"];
    } else {
      json input = given;
      input.erase("tick");
      entry.kind = Entry::Kind::input;
      entry.input = input_of(session, input, here);
    }
    snapshot.log.push_back(std::move(entry));
  }
  return snapshot;
}

namespace {

/// The file's moment of the session's scenario with `seed` and the session's settings.
std::unique_ptr<episode::Episode> restored_from(const LiveSession& live, std::int64_t seed, const json& file, const std::string& at) {
  const std::unique_ptr<episode::Episode> fresh = live.new_episode(live.session().shared_model(), seed);
  try {
    return fresh->restore(read_snapshot_log(fresh->session(), file, at), true);
  } catch (const core::Error& e) {
    if (e.code() != core::ErrorCode::conflict) throw;
    const json& details = e.details();
    const std::string pointer = details.contains("input") ? at + "/inputs/" + details["input"].dump() + "/tick" : at + "/state_hash";
    throw core::Error(core::ErrorCode::conflict, e.what(), {{"pointer", pointer}});
  }
}

}  // namespace

std::shared_ptr<LiveSession> start_from_snapshot(Registry& registry, ScenarioCatalogue& catalogue, const Caller& caller, const json& file,
                                                 NewSession settings) {
  const std::string at = "/snapshot";
  SnapshotOrigin origin = read_snapshot_origin(file, at);
  const auto entry = catalogue.find(origin.scenario, caller);
  if (!entry || !entry->source.model) {
    throw core::Error(core::ErrorCode::not_found, "no scenario '" + origin.scenario + "' on this server: upload it first, then start from the snapshot",
                      {{"pointer", at + "/scenario"}, {"id", origin.scenario}});
  }
  if (entry->content_sha256() != origin.scenario_sha256) {
    throw core::Error(core::ErrorCode::conflict,
                      "scenario '" + origin.scenario + "' on this server differs from the one the snapshot was taken with (sha256 " +
                          entry->content_sha256().substr(0, 12) + "…, the snapshot's " + origin.scenario_sha256.substr(0, 12) + "…)",
                      {{"pointer", at + "/scenario_sha256"}});
  }
  settings.model = entry->source.model;
  const scenario::SourceOptions options = catalogue.options(*entry);
  if (origin.controller) {
    json errors = json::array();
    settings.model = runs::with_controller(entry->source.document, *origin.controller, options.load, errors).model;
    for (json& error : errors) error["pointer"] = at + "/controller" + error.value("pointer", "");
    runs::throw_if_problems(errors);
  }
  if (origin.time_limit) {
    try {
      scenario::check_episode_ticks(*origin.time_limit, settings.model->dt, options.load.limits.max_episode_ticks, "time_limit");
    } catch (const core::Error& e) {
      malformed(at + "/time_limit", e.what());
    }
  }
  settings.scenario = origin.scenario;
  settings.scenario_sha256 = origin.scenario_sha256;
  settings.seed = origin.seed;
  settings.controller = origin.controller;
  settings.owner = caller.owner;
  settings.time_limit = origin.time_limit;
  settings.requests = origin.requests;
  const auto live = registry.create(std::move(settings));
  try {
    std::lock_guard lock(live->mutex);
    go_on_from(*live, restored_from(*live, live->seed, file, at));
  } catch (...) {
    registry.remove(live->id, caller);
    throw;
  }
  return live;
}

json reset_to_snapshot(LiveSession& live, const json& file, const std::string& at) {
  const SnapshotOrigin origin = read_snapshot_origin(file, at);
  const auto differs = [&](const char* what, const std::string& key) {
    throw core::Error(core::ErrorCode::conflict, std::string("the snapshot's session ran ") + what + " than session " + live.id + ": start a new session from it",
                      {{"pointer", at + "/" + key}});
  };
  if (origin.scenario != live.scenario || origin.scenario_sha256 != live.scenario_sha256) differs("another scenario", "scenario_sha256");
  if (origin.controller != live.controller) differs("another controller", "controller");
  if (origin.time_limit != live.time_limit || origin.requests != live.requests) differs("other run settings (time limit, requests)", "time_limit");
  // Everything that can fail is done before the session changes.
  std::unique_ptr<episode::Episode> restored = restored_from(live, origin.seed, file, at);
  live.seed = origin.seed;
  live.snapshots.clear();
  return go_on_from(live, std::move(restored));
}

}  // namespace hrisim::http
