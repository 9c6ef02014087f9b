#pragma once
// What the subcommands share: their arguments (options, seeds, durations), and the scenario files
// they read — hrisim's JSON, or IMHuS, Pedsim and HuNavSim files imported on the way — with errors
// printed at their pointers and lines.
#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "core/json_schema.hpp"
#include "scenario/import.hpp"
#include "scenario/load.hpp"
#include "scenario/source.hpp"

namespace hrisim::app {

/// Throws core::Error(bad_request) with `message`: the command exits with 2 and prints it.
[[noreturn]] void usage_error(const std::string& message);

/// A number of seconds >= 0 given to `option`.
double parse_seconds(const std::string& option, const std::string& text);

/// Arguments of a command: one file and options, each option with its values in order.
struct ParsedArgs {
  std::string file;                ///< the first file
  std::vector<std::string> files;  ///< every file, when the command takes several
  std::map<std::string, std::vector<std::string>> values;  ///< options that take a value
  std::set<std::string> flags;                              ///< options without one
  std::optional<std::string> last(const std::string& option) const {
    const auto found = values.find(option);
    return found == values.end() ? std::nullopt : std::optional(found->second.back());
  }
};

/// Reads `args`: options in `valued` take the next argument, those in `flags` none; one file, or
/// several when `many_files`. --help prints `usage` and exits; anything else is a usage error.
ParsedArgs parse_args(const std::vector<std::string>& args, const std::set<std::string>& valued, const std::set<std::string>& flags,
                      const std::string& usage, bool many_files = false);

/// Seeds of `--seeds`: "A-B" (inclusive) or "A,B,C".
std::vector<std::uint64_t> parse_seeds(const std::string& text);

/// How a file of another simulator is turned into a scenario.
struct SourceOptions {
  std::string format;  ///< "imhus", "pedsim", "hunav", or empty to tell by the file
  std::string dialect;  ///< Pedsim: "pedsim_ros", "libpedsim", or empty for the root element's
  std::string scenario;
  std::optional<std::filesystem::path> map;
};

/// --from, --dialect, --scenario and --map.
SourceOptions source_options(const ParsedArgs& parsed);

/// A file's format: --from's, else its extension's (.json, .xml: IMHuS or Pedsim by the content,
/// .yaml/.yml: HuNavSim), else its content's.
scenario::SourceFormat file_format(const std::string& file, std::string_view text, const SourceOptions& source);

std::optional<std::string> read_text(const std::string& file);

/// Imports an IMHuS or Pedsim XML file or a HuNavSim agents file; prints its warnings, and its errors
/// when there are any.
std::optional<scenario::ImportResult> import_file(const std::string& file, const std::string& text, scenario::SourceFormat format,
                                                  const SourceOptions& source);

/// A scenario file compiled: its text and format, native document, and the model (or the errors).
struct LoadedFile {
  std::string text;
  scenario::SourceFormat format = scenario::SourceFormat::json;
  nlohmann::json document;
  scenario::LoadOptions load;  ///< where its maps are found
  scenario::LoadResult result;
  std::optional<scenario::ImportResult> imported;  ///< an imported file's import, for the lines its parts came from
};

LoadedFile load(const std::string& file, const SourceOptions& source = {});

/// Errors as `FILE: POINTER: message`; for an imported file `FILE:LINE: POINTER: message`, at the XML
/// line the part at fault came from.
void print_errors(const std::string& file, const std::vector<core::ValidationError>& errors, const char* kind = "",
                  const scenario::ImportResult* imported = nullptr);
void print_errors(const std::string& file, const LoadedFile& loaded);

/// Folder of bundled scenarios and maps searched for relative map names (HRISIM_SCENARIOS, else "scenarios").
std::string bundled_scenarios_dir();

}  // namespace hrisim::app
