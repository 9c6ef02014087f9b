#pragma once
// Small scenarios for tests: a 10 m × 10 m walled room plus whatever the test adds.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "scenario/load.hpp"

namespace hrisim::testing {

/// A room from (0, 0) to (10, 10) with a table in the middle; `extra` is merged over it.
inline nlohmann::json room_scenario(const nlohmann::json& extra) {
  nlohmann::json scenario = nlohmann::json::parse(R"({
    "name": "room",
    "time_limit": 60,
    "world": {
      "bounds": {"min": [-0.5, -0.5], "max": [10.5, 10.5]},
      "walls": [{"from": [0, 0], "to": [10, 0]}, {"from": [10, 0], "to": [10, 10]},
                {"from": [10, 10], "to": [0, 10]}, {"from": [0, 10], "to": [0, 0]}],
      "obstacles": [{"name": "table", "box": {"x": 5, "y": 5, "length": 1.2, "width": 0.8}}]
    },
    "steps": []
  })");
  scenario.merge_patch(extra);
  return scenario;
}

/// `document` as a scenario written before routines had their name: "tasks", and "task" wherever a
/// routine is named (the former keys, still read with a warning at each).
inline nlohmann::json with_former_keys(nlohmann::json document) {
  const auto rename = [](nlohmann::json& object, const char* current, const char* former) {
    if (!object.is_object() || !object.contains(current)) return;
    object[former] = std::move(object[current]);
    object.erase(current);
  };
  const auto in_actions = [&](nlohmann::json& actions) {
    for (nlohmann::json& action : actions) {
      rename(action, "routine", "task");
      if (action.contains("request")) rename(action["request"], "routine", "task");
    }
  };
  rename(document, "routines", "tasks");
  if (document.contains("tasks")) {
    for (auto& [name, actions] : document["tasks"].items()) in_actions(actions);
  }
  if (document.contains("steps")) {
    for (nlohmann::json& step : document["steps"]) in_actions(step["actions"]);
  }
  for (const char* section : {"async", "requests"}) {
    if (!document.contains(section)) continue;
    for (nlohmann::json& entry : document[section]) rename(entry, "routine", "task");
  }
  return document;
}

/// Loads a scenario that must be valid (maps may be anywhere: these are the tests' own files).
inline std::shared_ptr<const scenario::Model> load_valid(const nlohmann::json& document) {
  scenario::LoadOptions options;
  options.limits.confine_files = false;
  const scenario::LoadResult result = scenario::load_scenario(document, options);
  for (const auto& error : result.errors) ADD_FAILURE() << error.pointer << ": " << error.message;
  return result.model;
}

/// The error a scenario gets at `pointer` (files may be anywhere, as in load_valid), or a failure
/// naming every error there was.
inline std::string error_at(const nlohmann::json& document, const std::string& pointer) {
  scenario::LoadOptions options;
  options.limits.confine_files = false;
  const auto errors = scenario::load_scenario(document, options).errors;
  for (const auto& error : errors) {
    if (error.pointer == pointer) return error.message;
  }
  std::string all;
  for (const auto& error : errors) all += "\n  " + error.pointer + ": " + error.message;
  ADD_FAILURE() << "no error at " << pointer << "; errors:" << all;
  return "";
}

}  // namespace hrisim::testing
