#include "app/sweep_file.hpp"

#include <algorithm>
#include <cstdio>
#include <set>

#include "app/command_line.hpp"
#include "core/error.hpp"

namespace hrisim::app {

using nlohmann::json;

std::string sweep_scenario_file(const std::string& entry, const std::filesystem::path& sweep_file) {
  if (entry.find('/') == std::string::npos && !std::filesystem::path(entry).has_extension()) {
    return (std::filesystem::path(bundled_scenarios_dir()) / (entry + ".json")).string();
  }
  const std::filesystem::path path(entry);
  return (path.is_absolute() ? path : sweep_file.parent_path() / path).string();
}

Sweep read_sweep(const std::string& file) {
  const auto text = read_text(file);
  if (!text) usage_error(file + ": cannot read the file");
  json document;
  try {
    document = json::parse(*text);
  } catch (const json::parse_error& e) {
    usage_error(file + ": not JSON: " + e.what());
  }
  std::vector<std::pair<std::string, std::string>> problems;
  const auto problem = [&](const std::string& pointer, const std::string& message) { problems.emplace_back(pointer, message); };
  Sweep sweep;
  if (!document.is_object()) {
    problem("", "a sweep is an object: {\"name\", \"scenarios\", \"controllers\", \"seeds\", \"gates\", ...}");
  } else {
    for (const auto& [key, value] : document.items()) {
      static const std::set<std::string> kKnown{"name", "scenarios", "controllers", "seeds", "gates", "max_time", "requests", "baseline_without_robot"};
      if (!kKnown.contains(key)) problem("/" + key, "unknown field (known: name, scenarios, controllers, seeds, gates, max_time, requests, baseline_without_robot)");
    }
    if (!document.contains("name") || !document["name"].is_string() || document["name"].get<std::string>().empty()) {
      problem("/name", "the sweep's name is required: part of each run's name and identity");
    } else {
      sweep.name = document["name"];
    }
    const json scenarios = document.value("scenarios", json());
    if (!scenarios.is_array() || scenarios.empty()) problem("/scenarios", "a list of one or more scenarios (a bundled one's name, or a file)");
    for (std::size_t i = 0; scenarios.is_array() && i < scenarios.size(); ++i) {
      if (!scenarios[i].is_string() || scenarios[i].get<std::string>().empty()) {
        problem("/scenarios/" + std::to_string(i), "a bundled scenario's name or a file's path");
      } else {
        const std::string path = sweep_scenario_file(scenarios[i], file);
        if (!std::filesystem::is_regular_file(path)) problem("/scenarios/" + std::to_string(i), "no scenario file " + path);
        sweep.scenarios.push_back(path);
      }
    }
    const json controllers = document.value("controllers", json::array({json()}));
    if (!controllers.is_array() || controllers.empty()) problem("/controllers", "a list of controllers ({\"type\": ...}, or null for the scenario's own)");
    for (std::size_t i = 0; controllers.is_array() && i < controllers.size(); ++i) {
      if (!controllers[i].is_null() && !controllers[i].is_object()) problem("/controllers/" + std::to_string(i), "a controller object, or null");
      sweep.controllers.push_back(controllers[i]);
    }
    const json seeds = document.value("seeds", json());
    if (seeds.is_string()) {
      try {
        sweep.seeds = parse_seeds(seeds);
      } catch (const core::Error& e) {
        problem("/seeds", e.what());
      }
    } else if (seeds.is_array() && !seeds.empty() && std::all_of(seeds.begin(), seeds.end(), [](const json& s) { return s.is_number_unsigned(); })) {
      sweep.seeds = seeds.get<std::vector<std::uint64_t>>();
    } else {
      problem("/seeds", "\"A-B\", \"A,B,C\" or a list of whole numbers");
    }
    const json gates = document.value("gates", json::array());
    if (!gates.is_array() || !std::all_of(gates.begin(), gates.end(), [](const json& g) { return g.is_string(); })) {
      problem("/gates", "a list of gates such as \"collisions.max == 0\"");
    } else {
      sweep.gates = gates.get<std::vector<std::string>>();
    }
    if (document.contains("max_time")) {
      if (!document["max_time"].is_number() || !(document["max_time"].get<double>() > 0.0)) {
        problem("/max_time", "seconds of simulation time, above 0");
      } else {
        sweep.max_time = document["max_time"].get<double>();
      }
    }
    const json requests = document.value("requests", json::array());
    for (std::size_t i = 0; i < (requests.is_array() ? requests.size() : 1); ++i) {
      const json& request = requests.is_array() ? requests[i] : requests;
      if (!request.is_object() || !request.value("time", json()).is_number() || !request.value("routine", json()).is_string()) {
        problem("/requests" + (requests.is_array() ? "/" + std::to_string(i) : ""), "a request is {\"time\": seconds, \"routine\": name}");
        continue;
      }
      sweep.requests.emplace_back(request["time"].get<double>(), request["routine"].get<std::string>());
    }
    if (document.contains("baseline_without_robot")) {
      if (!document["baseline_without_robot"].is_boolean()) problem("/baseline_without_robot", "true or false");
      else sweep.baseline_without_robot = document["baseline_without_robot"];
    }
  }
  for (const auto& [pointer, message] : problems) std::fprintf(stderr, "%s: %s: %s\n", file.c_str(), pointer.empty() ? "(document)" : pointer.c_str(), message.c_str());
  if (!problems.empty()) usage_error(file + ": " + std::to_string(problems.size()) + " problem" + (problems.size() == 1 ? "" : "s") + " in the sweep");
  return sweep;
}

}  // namespace hrisim::app
