#pragma once
// A run as asked for (by `hrisim run` or POST /api/v1/runs), checked and turned into a RunSpec: the
// controller applied to the scenario's robot under test, gates parsed, seeds checked. One place, so
// the CLI and the REST API accept and refuse the same things.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "runs/executor.hpp"
#include "scenario/load.hpp"

namespace hrisim::runs {

/// Most episodes one run may ask for.
inline constexpr std::size_t kMaxSeedsPerRun = 100000;

struct RunRequest {
  std::string scenario_id;
  std::string scenario_sha256;  ///< of its source, kept with the run for provenance
  nlohmann::json document;  ///< the scenario's native JSON
  scenario::LoadOptions load;
  std::vector<std::uint64_t> seeds;
  /// Replaces the built-in controller of the scenario's first robot, in the scenario's form
  /// ({"type": "goal", "goal": {...}}); the scenario's own when empty.
  std::optional<nlohmann::json> controller;
  std::optional<double> max_time;
  std::vector<std::string> gates;
  std::vector<std::pair<double, std::string>> requests;
  bool baseline_without_robot = false;  ///< measure human_path_deviation against the seed without robots
};

/// The scenario with `controller` replacing the built-in controller of its first robot (the robot
/// under test), in the scenario's form ({"type": "goal", "goal": {...}}). Problems in the controller
/// come back with pointers under "/controller"; `errors` gets them (and any in the scenario).
scenario::LoadResult with_controller(nlohmann::json document, const nlohmann::json& controller, const scenario::LoadOptions& load,
                                     nlohmann::json& errors);

/// The request that runs a stored episode again: `document` (its scenario as stored) with `load`, its
/// seed, and its run's controller, max_time and requests from the run's `config` (empty for an episode
/// without a run). Episodes stored before the rename of "task" to "routine" keep "task".
RunRequest replay_request(const nlohmann::json& document, const scenario::LoadOptions& load, const nlohmann::json& config, std::uint64_t seed);

/// Throws core::Error(bad_request) for a non-empty list of {pointer, message}: the first message (and
/// how many more), every one in details.errors, the first pointer in details.pointer.
void throw_if_problems(const nlohmann::json& errors);

/// Checks the request and builds the spec. Throws core::Error(bad_request) with every problem found
/// in details.errors, each with a pointer into the request ("/gates/1", "/controller/goal", "/seeds"):
/// `found` (the problems a reader of the request found already, first), then its own at other pointers.
RunSpec make_run_spec(const RunRequest& request, const nlohmann::json& found = nlohmann::json::array());

}  // namespace hrisim::runs
