#pragma once
// A sweep file: scenarios × controllers over the same seeds, gates and limits (hrisim sweep), read and
// checked with every problem said at its JSON pointer.
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hrisim::app {

/// A sweep file read: scenarios × controllers, each a run of the same seeds, gates and limits.
struct Sweep {
  std::string name;
  std::vector<std::string> scenarios;  ///< files, found as sweep_scenario_file() says
  std::vector<nlohmann::json> controllers;  ///< null: the scenario's own
  std::vector<std::uint64_t> seeds;
  std::vector<std::string> gates;
  std::optional<double> max_time;
  std::vector<std::pair<double, std::string>> requests;
  bool baseline_without_robot = false;
};

/// A sweep's scenario: a bundled one by its name ("elevator"), or a file relative to the sweep file.
std::string sweep_scenario_file(const std::string& entry, const std::filesystem::path& sweep_file);

/// Reads and checks a sweep file; every problem is printed as FILE: POINTER: MESSAGE, then a usage
/// error (exit 2).
Sweep read_sweep(const std::string& file);

}  // namespace hrisim::app
