#pragma once
// `hrisim run`, `hrisim sweep` and `hrisim merge`: running a scenario headless — one episode, a run of
// seeds, or a shard of a run split over machines — a sweep of scenarios × controllers, and merging
// shards' databases into one.
#include <string>
#include <vector>

namespace hrisim::app {

/// hrisim run FILE [--seed N | --seeds A-B|A,B,C] [--gate EXPR ...] [--junit FILE] [--db FILE] [--jobs N]
/// [--controller JSON] [--max-time S] [--events] [--request TIME:TASK ...] [--scenario NAME] [--map FILE]
/// [--trajectory FILE.csv]. One plain episode prints its summary (exit 0). With --seeds, --gate, --junit
/// or --db it is a run: episodes on --jobs threads, stored (in --db, or a scratch file), the run report
/// printed; exit 0 when the verdict passes, 1 when a gate fails or an episode did not finish. Exit 2 on
/// bad arguments or an invalid scenario. --shard K/N (or auto, auto/N) runs the K-th of N parts of the seeds
/// into --db, as the whole run (one id on every machine) for hrisim merge; --name names the run.
int run_command(const std::vector<std::string>& args);


/// hrisim sweep SWEEP.json [--db FILE] [--jobs N] [--shard K/N|auto|auto/N]: every scenario × controller
/// of the sweep file as a run of its seeds, gates and limits (each run's seeds split as hrisim run
/// --shard splits them); prints the runs' reports as {"runs": [...]}; exit 0 when every verdict passes.
int sweep_command(const std::vector<std::string>& args);

/// hrisim merge SHARD.db... --into RESULTS.db [--junit FILE]: merges every run of the databases (shards
/// of runs, or any runs) into RESULTS.db, each database in one transaction, refusing a shard that does
/// not belong to the run of its id there; prints the merged runs' reports like hrisim run and exits as
/// it does (0 when every verdict passes, 1 otherwise, 2 on bad arguments).
int merge_command(const std::vector<std::string>& args);

}  // namespace hrisim::app
