#pragma once
// `hrisim validate` and `hrisim run`: checking a scenario file and running it headless.
#include <string>
#include <vector>

namespace hrisim::app {

/// hrisim validate FILE...: prints every error with its JSON pointer; exit 0 when all are valid, 1 if not.
int validate_command(const std::vector<std::string>& args);

/// hrisim run FILE [--seed N] [--max-time S] [--events] [--request TIME:TASK ...] [--scenario NAME]
/// [--map FILE] [--trajectory FILE.csv]: runs a native JSON or an IMHuS/Pedsim XML file to the end and
/// prints a JSON summary; exit 0 when it ran (whether or not the choreography completed), 1 when the
/// scenario is invalid, 2 on bad arguments.
int run_command(const std::vector<std::string>& args);

/// hrisim import [--from imhus|pedsim] FILE [--scenario NAME] [--map FILE]: the native JSON on stdout,
/// warnings and errors (with XML lines) on stderr; exit 1 when the file cannot be imported.
int import_command(const std::vector<std::string>& args);

/// Folder of bundled scenarios and maps searched for relative map names.
std::string bundled_scenarios_dir();

}  // namespace hrisim::app
