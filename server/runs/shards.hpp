#pragma once
// Runs split over machines: a shard is the K-th of N disjoint parts of a run's seeds (or of a sweep's
// episodes), chosen by position so that every machine agrees without talking; its run has the id of
// the whole run, derived from what the run is, so that the shards' databases merge into one run.
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace hrisim::runs {

struct Shard {
  int index = 1;  ///< 1 to count
  int count = 1;
};

/// Reads an environment variable (std::getenv in the command line, a map in tests).
using VariableReader = std::function<std::optional<std::string>(const char* name)>;

/// Most shards a run may be split into.
inline constexpr int kMaxShards = 100000;

/// `--shard` as given: "K/N" (K from 1 to N), "auto" (the index and count a scheduler gives: Slurm's
/// SLURM_ARRAY_TASK_ID − SLURM_ARRAY_TASK_MIN + 1 of SLURM_ARRAY_TASK_COUNT, GitLab's CI_NODE_INDEX of
/// CI_NODE_TOTAL, CircleCI's CIRCLE_NODE_INDEX + 1 of CIRCLE_NODE_TOTAL, Buildkite's
/// BUILDKITE_PARALLEL_JOB + 1 of BUILDKITE_PARALLEL_JOB_COUNT) or "auto/N" (Kubernetes' Indexed Job:
/// JOB_COMPLETION_INDEX + 1 of N). Throws core::Error(bad_request) saying what is wrong or missing.
Shard parse_shard(const std::string& text, const VariableReader& environment);

/// The positions (0-based) of `total` items that shard `shard` takes: every N-th from K − 1, so parts
/// differ in size by one at most and neighbouring seeds go to different machines.
std::vector<std::size_t> shard_positions(std::size_t total, const Shard& shard);

/// The id of the run a shard belongs to: "r" and 32 hex digits of the SHA-256 of `identity` (what the
/// run is: its name, scenario, seeds, shard count, gates, limits), the same on every machine. What
/// must agree for the shards to be one run but is not its identity (the scenario's content, the
/// controller, hrisim's version) is checked when they are merged.
std::string shard_run_id(const nlohmann::json& identity);

}  // namespace hrisim::runs
