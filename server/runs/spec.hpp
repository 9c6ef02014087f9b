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
  /// Changes the built-in controller of the scenario's first robot, in the scenario's form
  /// ({"type": "goal", "goal": {...}}): over the scenario's own (see effective_controller), or whole
  /// when `controller_whole`; the scenario's own when empty.
  std::optional<nlohmann::json> controller;
  bool controller_whole = false;  ///< a replay: `controller` is the one the robot had
  std::optional<double> max_time;
  std::vector<std::string> gates;
  std::vector<std::pair<double, std::string>> requests;
  bool baseline_without_robot = false;  ///< measure human_path_deviation against the seed without robots
};

/// The controller of the scenario's first robot as written (null when it has none).
nlohmann::json scenario_controller(const nlohmann::json& document);

/// The controller a request gives the scenario's first robot: the scenario's own with the request's
/// fields replacing its fields (a field given as null removes it), so a swap of `type` keeps the
/// scenario's goal (location or pose, with its radius) and search parameters; a goal given replaces
/// the scenario's location or pose and keeps its radius unless it gives one. What the new type does
/// not take is left behind unless the request gives it: the goal for idle and teleop, `person` and
/// `strategy` for any type but search.
nlohmann::json effective_controller(const nlohmann::json& document, const nlohmann::json& requested);

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
