#pragma once
// Importers from the formats peers publish scenarios in, to hrisim's native JSON:
// IMHuS choreography XML (seeds 001/002), Pedsim scenario XML and HuNavSim agents YAML. Errors and
// warnings carry the line of the file they refer to.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scenario/load.hpp"

namespace hrisim::scenario {

struct ImportMessage {
  int line = 0;  ///< 1-based line in the imported file, 0 when it concerns the whole file
  std::string message;
};

struct ImportResult {
  nlohmann::ordered_json scenario;  ///< native scenario; meaningful only without errors
  std::vector<ImportMessage> errors;
  std::vector<ImportMessage> warnings;
  /// Where parts of the scenario come from: a JSON pointer into it and the line of the file it was read from.
  std::vector<std::pair<std::string, int>> origins;
};

/// The XML line the part of an imported scenario at `pointer` was read from (the longest recorded
/// prefix of it), or 0 when none was recorded.
int origin_line(const ImportResult& imported, std::string_view pointer);

struct ImportOptions {
  std::string scenario;                               ///< IMHuS: which scenario of the file; the first when empty
  std::optional<std::filesystem::path> map;           ///< a ROS map YAML or a world JSON replacing the file's map
  std::vector<std::filesystem::path> map_search_path;  ///< where IMHuS map names (maps/<name>.world.json) and HuNavSim world names (<name>.yaml, maps/<name>.yaml) are looked up
  std::string source_name;                            ///< file name, for the description
  ScenarioLimits limits;                              ///< people and files, as for loading
  /// Pedsim: whose social force parameters the people walk with, "pedsim_ros" or "libpedsim"; empty:
  /// pedsim_ros's for a <scenario> file (pedsim_ros overrides libpedsim's defaults), libpedsim's for
  /// a <welcome> file (libpedsim's own examples).
  std::string dialect;
};

/// pedsim_ros's social force parameters where they differ from libpedsim's (pedsim_simulator's
/// Config: obstacle σ 0.2 m instead of 0.8, social force factor 5.1 instead of 2.1).
inline constexpr double kPedsimRosObstacleSigma = 0.2;
inline constexpr double kPedsimRosSocialFactor = 5.1;

/// HuNavSim's people walk by lightsfm's social force model with hunav_loader's default factors (goal 2,
/// obstacle 10, social 5) and lightsfm's obstacle σ 0.2 m.
inline constexpr double kHunavGoalForceFactor = 2.0;
inline constexpr double kHunavObstacleForceFactor = 10.0;
inline constexpr double kHunavSocialForceFactor = 5.0;
inline constexpr double kHunavObstacleSigma = 0.2;

ImportResult import_imhus(std::string_view xml, const ImportOptions& options);
ImportResult import_pedsim(std::string_view xml, const ImportOptions& options);
/// A HuNavSim agents file (hunav_agent_manager's agents.yaml); errors and warnings carry its lines.
ImportResult import_hunav(std::string_view yaml, const ImportOptions& options);

/// "imhus" or "pedsim" from the document's content (Pedsim files have a single <scenario> root, or
/// <welcome> as libpedsim's examples).
std::string detect_xml_format(std::string_view xml);

/// Reads a world for --map: a ROS map YAML becomes {"map": path}; a .json file is a world object.
std::optional<nlohmann::ordered_json> world_from_file(const std::filesystem::path& file, std::string& error);

}  // namespace hrisim::scenario
