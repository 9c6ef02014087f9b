#pragma once
// Merging databases of shards (or of any runs) into one: every run with every episode, metric, event,
// trajectory and series, checked to belong together, each source in one transaction. Merging the same
// database twice changes nothing.
#include <optional>
#include <string>
#include <vector>

#include "storage/store.hpp"

namespace hrisim::runs {

struct MergedRun {
  std::string id;
  int added = 0;    ///< episodes copied
  int present = 0;  ///< episodes the target had already (the same seed with the same result)
};

/// Copies every finished run of `source` into `target`: a run the target does not have as it is; into
/// one it has (the same id: another shard of the same run, or the same database again), the episodes
/// of seeds it lacks, and the run's seeds become those of both, in the order of the whole run's list.
/// `source_name` and `target_name` (file names) are for messages; `owner`, when given, owns the runs
/// added (an import by a token's holder).
///
/// Throws core::Error(conflict), keeping nothing of `source`, when a run of it is not finished, or
/// differs from the run of the same id in `target` in its scenario's content (scenario_sha256),
/// hrisim's version, its controller or the shards it is split into, or a seed of it has another result
/// (state hash or status) there: the message names both values and both databases.
std::vector<MergedRun> merge_database(storage::Store& target, storage::Store& source, const std::string& source_name,
                                      const std::string& target_name, const std::optional<std::string>& owner = std::nullopt);

}  // namespace hrisim::runs
