#pragma once
// What a run amounts to, computed from the store alone so that the CLI and the REST API give the same
// answer: per-episode status, metric aggregates, the gate verdict, and a JUnit XML report.
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "metrics/gates.hpp"
#include "storage/store.hpp"

namespace hrisim::runs {

/// The gates stored in a run's config ("gates": [text, …]), parsed.
std::vector<metrics::Gate> gates_of(const storage::RunRecord& run);

/// The run with progress, per-episode status, aggregates of every metric and the verdict.
/// `live`: seeds still queued or running (Executor::live).
nlohmann::json run_report(const storage::RunRecord& run, const std::vector<storage::EpisodeRecord>& episodes,
                          const std::map<std::uint64_t, std::string>& live);

/// Run b against run a, metric by metric over their finished episodes: both means, b − a, a p-value
/// (Welch's t-test, or Fisher's exact test for 0/1 metrics), whether the difference is significant
/// at kSignificanceLevel, and whether b is then better or worse by the metric's direction.
nlohmann::json compare_runs(const storage::RunRecord& a, const std::vector<storage::EpisodeRecord>& a_episodes,
                            const storage::RunRecord& b, const std::vector<storage::EpisodeRecord>& b_episodes);

/// A run and its stored episodes, for comparing.
struct RunWithEpisodes {
  const storage::RunRecord* run;
  const std::vector<storage::EpisodeRecord>* episodes;
};

/// Two or more runs, metric by metric over their finished episodes: each run's distribution (count,
/// mean, std, min, quartiles, max and the values, for box and strip plots), and each later run against
/// the first (the baseline): the difference of means, the test as compare_runs makes it, its p-value
/// and, with `holm`, Holm's adjustment over every test of the reply; significance and the change
/// (better, worse) follow the adjusted p-value.
nlohmann::json compare_many_runs(const std::vector<RunWithEpisodes>& runs, bool holm);

/// A JUnit XML document of a report: one test case per gate, one per episode that did not finish
/// (error, cancelled, interrupted), so that it fails exactly when the verdict does.
std::string junit_xml(const nlohmann::json& report);

/// A metric value as JSON: the number, or null.
nlohmann::json metric_json(const storage::MetricValue& metric);

}  // namespace hrisim::runs
