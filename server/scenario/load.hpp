#pragma once
// Reading the native JSON scenario format (api/scenario.schema.json): structural checks against the
// schema, then meaning — every reference resolves, nobody starts inside a wall, compound tasks do not
// call themselves. All errors are collected, each with the JSON pointer of the value at fault.
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string_view>
#include <vector>

#include "core/json_schema.hpp"
#include "scenario/model.hpp"

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

struct LoadOptions {
  /// Folders where a relative `world.map` is looked up, in order (the scenario file's folder first).
  std::vector<std::filesystem::path> map_search_path;
};

/// The scenario JSON Schema shipped with this binary.
const core::JsonSchema& scenario_schema();

LoadResult load_scenario(const nlohmann::json& document, const LoadOptions& options);
/// Parses text first; a syntax error is reported with its line and column.
LoadResult load_scenario_text(std::string_view text, const LoadOptions& options);
/// Reads a file; map paths resolve against its folder, then `options.map_search_path`.
LoadResult load_scenario_file(const std::filesystem::path& file, LoadOptions options = {});

}  // namespace hrisim::scenario
