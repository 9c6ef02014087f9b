#pragma once
// Snapshots as files a user keeps: a moment of a live session written as JSON — the build that took it,
// the scenario (by id and content), seed, controller and settings, and the episode's input log as the
// API's own inputs — and read back (on this server or another of the same version) into a session
// that reaches that moment again, bit for bit. docs/api.md#snapshot-files describes the format.
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "episode/episode.hpp"
#include "http/scenario_catalogue.hpp"
#include "http/session_work.hpp"

namespace hrisim::http {

/// The format of snapshot files this server writes and reads (their `hrisim_snapshot`; api/openapi.yaml's
/// SnapshotFile, which also bounds an input log to 100,000 entries: the re-simulation it asks for is
/// bounded by the episode's time limit).
inline constexpr int kSnapshotFileFormat = 1;

/// The episode's input log as JSON: [{"tick", "steps", "action"?} | {"tick", "ticks"} | {"tick", "command"} |
/// {"tick", "place", "pose"}], each stamped with the tick it was given or began at.
nlohmann::json input_log_json(const scenario::Model& model, const std::vector<episode::Episode::Snapshot::Entry>& log);

/// The session's snapshot `id` as a file (the session's lock held).
nlohmann::json snapshot_file(const LiveSession& live, const std::string& id, const episode::Episode::Snapshot& snapshot);

/// What a session started from a snapshot file is made of, read from the file (at JSON pointer `at`).
/// Every file read here has passed the request contract (api/openapi.yaml's SnapshotFile, a part of
/// the bodies that carry one); what is checked here is what a schema cannot say.
struct SnapshotOrigin {
  std::string scenario, scenario_sha256;
  std::optional<nlohmann::json> controller;
  std::int64_t seed = 0;
  std::optional<double> time_limit;
  std::vector<std::pair<double, std::string>> requests;
};
/// 409 for a file of another hrisim version.
SnapshotOrigin read_snapshot_origin(const nlohmann::json& file, const std::string& at);
/// The file's moment and input log, read against the session its origin made (400 at the pointer of an
/// input out of tick order or one this scenario cannot take).
episode::Episode::Snapshot read_snapshot_log(const sim::Session& session, const nlohmann::json& file, const std::string& at);
/// A new session at the file's moment: made as its origin says (the scenario found as `caller` may see
/// it; 404 without it, 409 when its content differs), in the mode of `settings`, then driven by the
/// file's inputs. Re-simulates up to the file's tick (hold a place of Registry::admit_simulation); on
/// any error no session is left.
std::shared_ptr<LiveSession> start_from_snapshot(Registry& registry, ScenarioCatalogue& catalogue, const Caller& caller, const nlohmann::json& file,
                                                 NewSession settings);
/// Gymnasium's reset to the file's moment (POST …/reset {"options": {"snapshot": file}}): the session
/// must run the scenario, controller and settings the file names (409 otherwise); its seed becomes the
/// file's and its snapshots are dropped, as a reset's. Re-simulates up to the file's tick.
nlohmann::json reset_to_snapshot(LiveSession& live, const nlohmann::json& file, const std::string& at);

}  // namespace hrisim::http
