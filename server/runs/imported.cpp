#include "runs/imported.hpp"

#include <cmath>
#include <set>

#include "core/bounded_json.hpp"
#include "core/error.hpp"
#include "core/sha256.hpp"
#include "core/text.hpp"
#include "metrics/definitions.hpp"
#include "metrics/gates.hpp"
#include "runs/labels.hpp"
#include "runs/spec.hpp"

namespace hrisim::runs {
namespace {

using nlohmann::json;

/// Longest short text of a record (a kind, subject, agent id, termination, version), in bytes.
constexpr std::size_t kMaxShortText = 256;
/// Longest reason a metric has no value, in bytes.
constexpr std::size_t kMaxNullReason = 1024;
/// Largest seed, as the API takes it (2^53 − 1: exact in JSON's numbers).
constexpr std::uint64_t kMaxImportedSeed = 9007199254740991ULL;

[[noreturn]] void refuse(const std::string& source, const std::string& what, const std::string& why) {
  throw core::Error(core::ErrorCode::bad_request, source + ": " + what + " " + why);
}

bool is_hex(const std::string& text, std::size_t length) {
  return text.size() == length && text.find_first_not_of("0123456789abcdef") == std::string::npos;
}

bool short_text(const std::string& text, std::size_t most = kMaxShortText) { return text.size() <= most && text.find('\0') == std::string::npos; }

bool is_time(const std::string& text) {
  // RFC 3339 UTC as SQLite's strftime makes it: 2026-12-04T21:19:06.123Z (fraction optional).
  if (text.size() < 20 || text.size() > 30 || text[4] != '-' || text[10] != 'T' || text.back() != 'Z') return false;
  return text.find_first_not_of("0123456789-:.TZ") == std::string::npos;
}

bool is_status(const std::string& status) {
  static const std::set<std::string> kStatuses = {"finished", "failed", "error", "cancelled", "interrupted", "running", "queued"};
  return kStatuses.contains(status);
}

void check_controller(const json& controller, const std::string& source, const std::string& what) {
  if (controller.is_null()) return;
  if (!controller.is_object() || controller.size() > 4) refuse(source, what, "is not a controller (an object of type, goal, person and strategy)");
  for (const auto& [key, value] : controller.items()) {
    if (key != "type" && key != "goal" && key != "person" && key != "strategy") refuse(source, what, "has an unknown field '" + key.substr(0, 32) + "'");
  }
}

void check_config(const storage::RunRecord& run, const std::string& source) {
  const json& config = run.config;
  const std::string what = "run " + run.id + "'s config";
  if (!config.is_object()) refuse(source, what, "is not an object");
  const json seeds = config.value("seeds", json());
  if (!seeds.is_array() || seeds.empty() || seeds.size() > kMaxSeedsPerRun) {
    refuse(source, what, "has no list of 1 to " + std::to_string(kMaxSeedsPerRun) + " seeds");
  }
  std::set<std::uint64_t> distinct;
  for (const json& seed : seeds) {
    if (!seed.is_number_unsigned() || seed.get<std::uint64_t>() > kMaxImportedSeed) refuse(source, what, "has a seed that is not a whole number from 0 to 2^53 - 1");
    if (!distinct.insert(seed.get<std::uint64_t>()).second) refuse(source, what, "lists seed " + std::to_string(seed.get<std::uint64_t>()) + " twice");
  }
  const json gates = config.value("gates", json::array());
  if (!gates.is_array()) refuse(source, what, "has gates that are not a list");
  for (const json& gate : gates) {
    if (!gate.is_string() || !short_text(gate.get<std::string>())) refuse(source, what, "has a gate that is not text");
    try {
      metrics::parse_gate(gate.get<std::string>());
    } catch (const core::Error& e) {
      refuse(source, what, std::string("has a gate that does not parse: ") + e.what());
    }
  }
  check_controller(config.value("controller", json()), source, what + "'s controller");
  check_controller(config.value("effective_controller", json()), source, what + "'s effective_controller");
  const json max_time = config.value("max_time", json());
  if (!max_time.is_null() && !(max_time.is_number() && std::isfinite(max_time.get<double>()) && max_time.get<double>() > 0)) {
    refuse(source, what, "has a max_time that is not a number of seconds > 0");
  }
  const json requests = config.value("requests", json::array());
  if (!requests.is_array()) refuse(source, what, "has requests that are not a list");
  for (const json& request : requests) {
    const bool fine = request.is_object() && request.contains("time") && request["time"].is_number() && std::isfinite(request["time"].get<double>()) &&
                      (request.value("routine", json()).is_string() || request.value("task", json()).is_string());
    if (!fine) refuse(source, what, "has a request that is not {time, routine}");
  }
  const json sha = config.value("scenario_sha256", json());
  if (!sha.is_string() || !is_hex(sha.get<std::string>(), 64)) refuse(source, what, "has no scenario_sha256 of 64 hex digits");
  for (const char* key : {"hrisim_version", "git_commit", "scenario"}) {
    const json value = config.value(key, json(""));
    if (!value.is_string() || !short_text(value.get<std::string>())) refuse(source, what, std::string("has a ") + key + " that is not short text");
  }
  const json sharding = config.value("sharding", json());
  if (!sharding.is_null()) {
    const bool fine = sharding.is_object() && sharding.value("count", json()).is_number_unsigned() && sharding.value("of_seeds", json()).is_array() &&
                      sharding["of_seeds"].size() <= kMaxSeedsPerRun &&
                      (!sharding.contains("merged") || (sharding["merged"].is_array() && sharding["merged"].size() <= kMaxSeedsPerRun));
    if (!fine) refuse(source, what, "has a sharding that is not {count, of_seeds, index or merged}");
    try {
      (void)sharding["of_seeds"].get<std::vector<std::uint64_t>>();
      if (sharding.contains("merged")) (void)sharding["merged"].get<std::set<int>>();
      (void)sharding.value("index", 0);
    } catch (const json::exception&) {
      refuse(source, what, "has a sharding of the wrong types");
    }
  }
}

}  // namespace

bool is_record_id(const std::string& id, char prefix) { return id.size() == 33 && id[0] == prefix && is_hex(id.substr(1), 32); }

bool is_content_addressed(const std::string& scenario_id) { return is_record_id(scenario_id, 'b') || is_record_id(scenario_id, 'f'); }

void check_imported_run(const storage::RunRecord& run, const std::string& source) {
  if (!is_record_id(run.id, 'r')) refuse(source, "a run", "has an id that is not 'r' and 32 hex digits");
  const std::string what = "run " + run.id;
  if (!is_record_id(run.scenario_id, 'b') && !is_record_id(run.scenario_id, 'f') && !is_record_id(run.scenario_id, 'u')) {
    refuse(source, what, "names a scenario by an id hrisim does not make");
  }
  if (run.controller.empty() || run.controller.size() > 32 || run.controller.find_first_not_of("abcdefghijklmnopqrstuvwxyz_") != std::string::npos) {
    refuse(source, what, "has a controller that is not a controller's type");
  }
  if (!is_time(run.created_at) || (run.finished_at && !is_time(*run.finished_at))) refuse(source, what, "has times that are not RFC 3339");
  if (const json problems = label_problems(run.name, run.tags, run.notes); !problems.empty()) {
    refuse(source, what, "has labels the API would refuse: " + problems[0]["pointer"].get<std::string>() + ": " + problems[0]["message"].get<std::string>());
  }
  check_config(run, source);
}

void check_imported_episode(const storage::EpisodeRecord& episode, const storage::RunRecord& run, const std::string& source) {
  if (!is_record_id(episode.id, 'e')) refuse(source, "an episode of run " + run.id, "has an id that is not 'e' and 32 hex digits");
  const std::string what = "episode " + episode.id;
  if (episode.run_id != run.id || episode.scenario_id != run.scenario_id || episode.controller != run.controller) {
    refuse(source, what, "does not belong to its run (run, scenario or controller differ)");
  }
  const std::vector<std::uint64_t> seeds = run.config["seeds"].get<std::vector<std::uint64_t>>();
  if (std::find(seeds.begin(), seeds.end(), episode.seed) == seeds.end()) refuse(source, what, "has a seed its run does not list");
  if (!is_status(episode.status) || !short_text(episode.termination_reason) || episode.ticks < 0 || !std::isfinite(episode.sim_time) ||
      episode.sim_time < 0 || !is_time(episode.created_at) || !(episode.state_hash.empty() || is_hex(episode.state_hash, 16))) {
    refuse(source, what, "has a status, termination, length, time or state hash hrisim does not make");
  }
  std::set<std::string> keys;
  for (const storage::MetricValue& metric : episode.metrics) {
    const bool fine = metrics::find_definition(metric.key) && keys.insert(metric.key).second &&
                      (metric.value ? std::isfinite(*metric.value) && !metric.null_reason : metric.null_reason && short_text(*metric.null_reason, kMaxNullReason));
    if (!fine) refuse(source, what, "has a metric that is not a known metric's finite value or reason");
  }
  for (const storage::EventRecord& event : episode.events) {
    if (event.tick < 0 || !std::isfinite(event.time) || !short_text(event.kind) || !short_text(event.subject) || !event.data.is_object()) {
      refuse(source, what, "has an event that is not {tick, time, kind, subject, data object}");
    }
  }
  for (const storage::TrajectorySample& sample : episode.trajectory) {
    if (sample.tick < 0 || !short_text(sample.agent_id) || !std::isfinite(sample.x) || !std::isfinite(sample.y) || !std::isfinite(sample.theta)) {
      refuse(source, what, "has a trajectory sample that is not a finite pose at a tick");
    }
  }
  for (const storage::SeriesRecord& series : episode.series) {
    const auto& known = metrics::series_definitions();
    const bool named = std::any_of(known.begin(), known.end(), [&](const metrics::SeriesDefinition& d) { return d.name == series.name; });
    const bool finite = std::all_of(series.values.begin(), series.values.end(), [](const std::optional<double>& v) { return !v || std::isfinite(*v); });
    if (!named || !finite || series.first_tick < 0 || series.stride < 1) refuse(source, what, "has a series hrisim does not record");
  }
}

void check_imported_scenario(const storage::ScenarioRecord& scenario, const std::string& source) {
  const std::string what = "scenario " + (scenario.id.size() <= 40 ? scenario.id : scenario.id.substr(0, 40) + "…");
  if (!is_record_id(scenario.id, 'b') && !is_record_id(scenario.id, 'f') && !is_record_id(scenario.id, 'u')) {
    refuse(source, what, "has an id hrisim does not make");
  }
  static const std::set<std::string> kFormats = {"json", "imhus_xml", "pedsim_xml", "hunav_yaml"};
  if (!short_text(scenario.name) || !kFormats.contains(scenario.format) || scenario.source.find('\0') != std::string::npos || !is_time(scenario.created_at)) {
    refuse(source, what, "has a name, format or source hrisim does not store");
  }
  for (const auto& [path, bytes] : scenario.files) {
    if (const std::string problem = storage::scenario_file_path_problem(path); !problem.empty()) refuse(source, what, "has a file whose path is wrong: " + problem);
  }
  if (scenario.sha256 != storage::scenario_sha256(scenario.source, scenario.files)) refuse(source, what, "has a sha256 that is not its content's");
  if (is_record_id(scenario.id, 'f') && (!scenario.files.empty() || scenario.sha256.substr(0, 32) != scenario.id.substr(1))) {
    refuse(source, what, "is named by a content hash that is not its content's");
  }
  if (is_record_id(scenario.id, 'b')) {
    // A bundled scenario's snapshot: named by the hash of its document's compact JSON text.
    json document;
    try {
      document = core::parse_bounded_json(scenario.source, what);
    } catch (const core::Error& e) {
      refuse(source, what, std::string("has a source that is not a scenario's JSON: ") + e.what());
    }
    if (!scenario.files.empty() || core::sha256_hex(core::json_text(document)).substr(0, 32) != scenario.id.substr(1)) {
      refuse(source, what, "is named by a content hash that is not its content's");
    }
  }
}

}  // namespace hrisim::runs
