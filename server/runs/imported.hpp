#pragma once
// The values of a database that came from elsewhere (an import, a shard to merge), checked as the same
// values arriving through the API are, before anything of it is stored: ids of hrisim's forms, scenario
// file paths that stay below their scenario, labels, configs, content that hashes to the id naming it.
#include <string>

#include "storage/store.hpp"

namespace hrisim::runs {

/// Whether `id` has the form of a stored record's id: `prefix` then 32 lowercase hex digits (an
/// unguessable id, or the start of a content hash).
bool is_record_id(const std::string& id, char prefix);

/// Throws core::Error(bad_request), naming `source` and what is wrong, for a run record unlike those
/// hrisim stores: its id, scenario id, controller, config (seeds, gates, controllers, time limit,
/// requests, hashes), labels or times.
void check_imported_run(const storage::RunRecord& run, const std::string& source);

/// The same for an episode of `run`: its ids, seed (one of the run's), numbers, metrics (known keys,
/// finite values), events, trajectory and series.
void check_imported_episode(const storage::EpisodeRecord& episode, const storage::RunRecord& run, const std::string& source);

/// The same for a scenario record: its id's form, name, format, files' paths (relative, below the
/// scenario) and content: its sha256 is that of its source and files, and an id made from content
/// (b: a bundled scenario's document, f: a file run by `hrisim run`) is that content's.
void check_imported_scenario(const storage::ScenarioRecord& scenario, const std::string& source);

/// Whether the scenario id is made from its content (b and f), so that any record of that id holds the
/// same content.
bool is_content_addressed(const std::string& scenario_id);

}  // namespace hrisim::runs
