#include "http/snapshot_files.hpp"

#include <cmath>

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

const json& member(const json& file, const char* key, const std::string& at) {
  if (!file.contains(key)) malformed(at + "/" + key, std::string(key) + " is required in a snapshot file");
  return file[key];
}

std::string text_member(const json& file, const char* key, const std::string& at) {
  const json& value = member(file, key, at);
  if (!value.is_string()) malformed(at + "/" + key, std::string(key) + ": a string");
  return value.get<std::string>();
}

/// A state hash as the API writes it: 16 hexadecimal digits.
std::uint64_t hash_of(const json& value, const std::string& at) {
  const std::string text = value.is_string() ? value.get<std::string>() : "";
  if (text.size() != 16 || text.find_first_not_of("0123456789abcdef") != std::string::npos) malformed(at, "state_hash: 16 hexadecimal digits");
  return std::stoull(text, nullptr, 16);
}

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
  if (!file.is_object()) malformed(at, "a snapshot file is an object (GET /api/v1/sessions/{id}/snapshots/{snapshot} gives one)");
  refuse_unknown_keys(file, {"hrisim_snapshot", "hrisim", "snapshot", "session", "scenario", "scenario_sha256", "seed", "controller", "time_limit",
                             "requests", "tick", "state_hash", "inputs"},
                      at);
  const json& format = member(file, "hrisim_snapshot", at);
  if (format != kSnapshotFileFormat) malformed(at + "/hrisim_snapshot", "hrisim_snapshot: this server reads snapshot files of format " + std::to_string(kSnapshotFileFormat));
  const json& build = member(file, "hrisim", at);
  const std::string version = build.is_object() && build.contains("version") && build["version"].is_string() ? build["version"].get<std::string>() : "";
  if (version.empty()) malformed(at + "/hrisim/version", "hrisim.version: the version of hrisim that took the snapshot");
  if (version != core::version()) {
    throw core::Error(core::ErrorCode::conflict,
                      "the snapshot was taken by hrisim " + version + "; this server is hrisim " + core::version() +
                          ": a snapshot file starts a session only on a server of the version that took it",
                      {{"pointer", at + "/hrisim/version"}, {"snapshot_version", version}, {"server_version", core::version()}});
  }
  SnapshotOrigin origin;
  origin.scenario = text_member(file, "scenario", at);
  origin.scenario_sha256 = text_member(file, "scenario_sha256", at);
  origin.seed = integer_field(file, "seed", 0, kMaxSeed, 0, at);
  member(file, "seed", at);
  if (file.contains("controller")) {
    if (!file["controller"].is_object()) malformed(at + "/controller", "controller: an object, as the session's");
    origin.controller = file["controller"];
  }
  if (file.contains("time_limit")) {
    const json& limit = file["time_limit"];
    if (!limit.is_number() || !(limit.get<double>() > 0.0) || !std::isfinite(limit.get<double>())) malformed(at + "/time_limit", "time_limit: seconds above 0");
    origin.time_limit = limit.get<double>();
  }
  if (file.contains("requests")) {
    const json& requests = file["requests"];
    if (!requests.is_array()) malformed(at + "/requests", "requests: a list of {time, routine}");
    for (std::size_t i = 0; i < requests.size(); ++i) {
      const std::string here = at + "/requests/" + std::to_string(i);
      const json& request = requests[i];
      if (!request.is_object() || !request.contains("time") || !request["time"].is_number() || !std::isfinite(request["time"].get<double>()) ||
          !request.contains("routine") || !request["routine"].is_string()) {
        malformed(here, "a request is {time: seconds, routine: name}");
      }
      refuse_unknown_keys(request, {"time", "routine"}, here);
      origin.requests.emplace_back(request["time"].get<double>(), request["routine"].get<std::string>());
    }
  }
  return origin;
}

episode::Episode::Snapshot read_snapshot_log(const sim::Session& session, const json& file, const std::string& at) {
  episode::Episode::Snapshot snapshot;
  snapshot.tick = integer_field(file, "tick", 0, std::numeric_limits<std::int64_t>::max(), 0, at);
  member(file, "tick", at);
  snapshot.state_hash = hash_of(member(file, "state_hash", at), at + "/state_hash");
  const json& inputs = member(file, "inputs", at);
  if (!inputs.is_array() || inputs.size() > kMaxSnapshotInputs) {
    malformed(at + "/inputs", "inputs: a list of at most " + std::to_string(kMaxSnapshotInputs) + " entries, as the file was written");
  }
  std::int64_t last_tick = 0;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const std::string here = at + "/inputs/" + std::to_string(i);
    const json& given = inputs[i];
    if (!given.is_object()) malformed(here, "an input is an object");
    Entry entry;
    entry.tick = integer_field(given, "tick", last_tick, snapshot.tick, -1, here);
    if (entry.tick < 0) malformed(here + "/tick", "tick: the tick it was given at is required");
    last_tick = entry.tick;
    json rest = given;
    rest.erase("tick");
    if (rest.contains("steps")) {
      refuse_unknown_keys(rest, {"steps", "action"}, here);
      entry.kind = Entry::Kind::step;
      entry.count = integer_field(rest, "steps", 0, std::numeric_limits<std::int64_t>::max(), 0, here);
      if (rest.contains("action")) entry.action = action_at(rest["action"], here + "/action");
    } else if (rest.contains("ticks")) {
      refuse_unknown_keys(rest, {"ticks"}, here);
      entry.kind = Entry::Kind::ticks;
      entry.count = integer_field(rest, "ticks", 1, std::numeric_limits<std::int64_t>::max(), 0, here);
    } else {
      entry.kind = Entry::Kind::input;
      entry.input = input_of(session, rest, here);
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
