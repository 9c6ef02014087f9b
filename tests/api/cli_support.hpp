#pragma once
// What tests of the command line share: how they call hrisim, and an episode's stored content to compare.
#include <nlohmann/json.hpp>
#include <string>

#include "storage/store.hpp"

namespace hrisim::testing {

// The bundled scenarios (and their maps) are found through HRISIM_SCENARIOS, whatever the working folder.
inline const std::string kHrisim = "HRISIM_SCENARIOS=" + std::string(HRISIM_SOURCE_DIR) + "/scenarios " + HRISIM_BINARY;
inline const std::string kScenarios = std::string(HRISIM_SOURCE_DIR) + "/scenarios";

/// Everything stored for one episode that the simulation decided, as comparable text.
inline std::string stored_content(storage::Store& store, const std::string& id) {
  const auto episode = store.episode(id);
  if (!episode) return "missing";
  nlohmann::json content = {{"seed", episode->seed}, {"termination", episode->termination_reason}, {"ticks", episode->ticks},
                            {"state_hash", episode->state_hash}, {"metrics", nlohmann::json::array()},
                            {"events", nlohmann::json::array()}, {"trajectory", nlohmann::json::array()}, {"series", nlohmann::json::array()}};
  for (const auto& metric : episode->metrics) content["metrics"].push_back({metric.key, metric.value ? nlohmann::json(*metric.value) : nlohmann::json()});
  for (const auto& event : episode->events) content["events"].push_back({event.tick, event.kind, event.subject, event.data});
  for (const auto& sample : episode->trajectory) content["trajectory"].push_back({sample.agent_id, sample.tick, sample.x, sample.y, sample.theta});
  for (const auto& series : store.series(id)) {
    nlohmann::json values = nlohmann::json::array();
    for (const auto& value : series.values) values.push_back(value ? nlohmann::json(*value) : nlohmann::json());
    content["series"].push_back({series.name, series.first_tick, series.stride, values});
  }
  return content.dump();
}

}  // namespace hrisim::testing
