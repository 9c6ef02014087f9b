#pragma once
// Scenario sources as people hand them in — native JSON, IMHuS XML, Pedsim XML, HuNavSim YAML — compiled
// to the native document and the model, every problem located (a JSON pointer into the native
// document, or a line of the imported file). The CLI and the REST API both go through here.
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scenario/import.hpp"
#include "scenario/load.hpp"

namespace hrisim::scenario {

enum class SourceFormat { json, imhus_xml, pedsim_xml, hunav_yaml };

/// "json", "imhus_xml", "pedsim_xml" or "hunav_yaml", as stored.
std::string_view to_string(SourceFormat format);
/// A format by name: json, imhus, pedsim, hunav, or the stored names.
std::optional<SourceFormat> source_format(std::string_view name);
/// XML (IMHuS or Pedsim, by its content) when the text starts with '<'; HuNavSim YAML when it starts
/// with neither '{' nor '[' and lists agents; JSON otherwise.
SourceFormat detect_source_format(std::string_view text);

/// A problem with a source: at `pointer` in the native document, or at `line` of the imported file.
struct SourceIssue {
  std::string pointer;
  int line = 0;
  std::string message;
  /// {"pointer": …}, {"line": …} or both (what validation found in an imported scenario, at the XML
  /// line it came from), with "message".
  nlohmann::json to_json() const;
};

struct CompiledSource {
  SourceFormat format = SourceFormat::json;
  nlohmann::json document;             ///< the native scenario (imported from XML when needed)
  std::shared_ptr<const Model> model;  ///< null when there are errors
  std::vector<SourceIssue> errors;
  std::vector<SourceIssue> warnings;
};

struct SourceOptions {
  ImportOptions import;  ///< for imported sources
  LoadOptions load;      ///< where maps are looked up
};

CompiledSource compile_source(std::string_view text, SourceFormat format, const SourceOptions& options);

/// What a list shows of a scenario: name, description, humans, robots (with their models), task,
/// duration (its time limit, s), steps, dt.
nlohmann::json summarize(const Model& model);

/// What a map view draws of a scenario, in the map frame (m, rad): the map's bounds; its walls as the
/// segments range sensors see (with their tops, null for full height); obstacles as polygons with
/// their height and furniture mesh; doors; elevators (door names); locations; social spaces with
/// their slots; and every agent with its kind, type, robot model, radius and start pose.
nlohmann::json world_geometry(const Model& model);

}  // namespace hrisim::scenario
