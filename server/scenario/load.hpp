#pragma once
// Reading the native JSON scenario format (api/scenario.schema.json): structural checks against the
// schema, then meaning — every reference resolves, nobody starts inside a wall, routines do not call
// themselves. All errors are collected, each with the JSON pointer of the value at fault.
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string_view>
#include <vector>

#include "core/json_schema.hpp"
#include "scenario/model.hpp"
#include "world/occupancy_grid.hpp"

namespace hrisim::scenario {

struct LoadResult {
  std::shared_ptr<const Model> model;  ///< null when there are errors
  std::vector<core::ValidationError> errors;
  std::vector<core::ValidationError> warnings;  ///< valid, but probably not what the author meant
};

/// How close to an obstacle a social-force human walking at `speed` can get: where the obstacle's
/// push equals the driving force, r + σ·ln(obstacle factor / (desired factor · speed / τ)); the
/// radius alone when the drive always wins.
double social_force_standoff(const humans::SocialForceParams& params, double radius, double speed);

/// Most people (humans and robots) one scenario may hold; `--max-people`.
inline constexpr int kDefaultMaxPeople = 2000;
/// Most ticks one episode may last (its time limit over dt; a run's max_time likewise): an hour at
/// 60 Hz. Bounds the simulated time, the work and the recording of a session or a run's episode;
/// `--max-episode-ticks`.
inline constexpr std::int64_t kDefaultMaxEpisodeTicks = 216'000;

/// What one scenario may ask of whoever compiles it: the server's flags set these (docs/limits.md).
struct ScenarioLimits {
  int max_people = kDefaultMaxPeople;
  std::int64_t max_episode_ticks = kDefaultMaxEpisodeTicks;
  std::int64_t max_grid_cells = world::kDefaultMaxGridCells;
  /// Files (maps) only inside the search path's folders; the command line turns this off for a
  /// user's own files.
  bool confine_files = true;
};

struct LoadOptions {
  /// Folders where a relative `world.map` is looked up, in order (the scenario file's folder first).
  std::vector<std::filesystem::path> map_search_path;
  ScenarioLimits limits;
};

/// Ticks an episode of `time_limit` seconds lasts at `dt`; an error naming `flag` when that is more
/// than `max_ticks` (`what` says whose time limit it is).
void check_episode_ticks(double time_limit, double dt, std::int64_t max_ticks, const std::string& what);

/// The scenario JSON Schema shipped with this binary.
const core::JsonSchema& scenario_schema();

/// A document with the former names of keys (former_keys.hpp) loads as with the current ones, with a
/// warning at each; every pointer said is one into the document as written.
LoadResult load_scenario(const nlohmann::json& document, const LoadOptions& options);
/// The JSON of a scenario's text; throws core::Error(bad_request) for a syntax error, at its line and
/// column ("invalid JSON at line 3, column 13: …").
nlohmann::json parse_scenario_json(std::string_view text);
/// Parses text first; a syntax error is reported with its line and column.
LoadResult load_scenario_text(std::string_view text, const LoadOptions& options);
/// Reads a file; map paths resolve against its folder, then `options.map_search_path`.
LoadResult load_scenario_file(const std::filesystem::path& file, LoadOptions options = {});

}  // namespace hrisim::scenario
