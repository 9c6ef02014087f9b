#pragma once
// Merging databases of shards (or of any runs) into one: every run with every episode, metric, event,
// trajectory and series, checked to belong together, each source in one transaction. Merging the same
// database twice changes nothing.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "storage/foreign.hpp"
#include "storage/store.hpp"

namespace hrisim::runs {

struct MergedRun {
  std::string id;   ///< the run's id in the target
  std::string source_id;  ///< its id in the source: another only for an import whose id another owner holds
  int added = 0;    ///< episodes copied
  int present = 0;  ///< episodes the target had already (the same seed with the same result)
};

/// Checks one run of a source as the same run asked for through the API would be checked: its config
/// compiled against its scenario (controller, time limit, requests). Throws core::Error(bad_request).
using RunCheck = std::function<void(const storage::ScenarioRecord& scenario, const storage::RunRecord& run)>;

/// Copies every finished run of `source` into `target`: a run the target does not have as it is; into
/// one it has (the same id: another shard of the same run, or the same database again), the episodes
/// of seeds it lacks, and the run's seeds become those of both, in the order of the whole run's list.
///
/// Everything of the source is read and checked first (runs::check_imported_*: values as the API
/// would take them, scenarios whose content is what their ids say, then `check_run`, when given), and
/// only then is the target
/// locked and written. `target_name` (a file name) is for messages. `owner`, when given (an import by
/// a token's holder), owns the runs and uploaded scenarios added; a run of an id another owner holds
/// gets an id of its own for this owner, and an uploaded scenario's id another owner holds a new one.
///
/// Throws core::Error(bad_request) for a value hrisim would not store, and core::Error(conflict),
/// keeping nothing of `source`, when a run of it is not finished, or differs from the run of the same
/// id in `target` in its scenario's content (scenario_sha256), hrisim's version, its controller or the
/// shards it is split into, or a seed of it has another result (state hash or status) there: without
/// `owner`, the message names both values and both databases; with one, it names none of the target's.
std::vector<MergedRun> merge_database(storage::Store& target, storage::ForeignDatabase& source, const std::string& target_name,
                                      const std::optional<std::string>& owner = std::nullopt, const RunCheck& check_run = {});

}  // namespace hrisim::runs
