#pragma once
// Builders of stored records for storage tests: deterministic content derived from an index.
#include <string>

#include "storage/store.hpp"

namespace hrisim::testing {

inline storage::ScenarioRecord make_scenario(const std::string& id) {
  return {id, "Scenario " + id, "json", R"({"name":")" + id + R"(","humans":[]})", "", "", "", "", {}};
}

/// An episode with `metrics` metric values (the last one null with a reason), `events` events and
/// `agents` × `ticks` trajectory samples, all derived from `index`.
inline storage::EpisodeRecord make_episode(const std::string& scenario_id, int index, int metrics = 10,
                                           int events = 5, int agents = 3, int ticks = 100) {
  storage::EpisodeRecord episode;
  episode.id = "episode-" + std::to_string(index);
  episode.scenario_id = scenario_id;
  episode.seed = 1000u + static_cast<std::uint64_t>(index);
  episode.controller = "teleop";
  episode.status = "succeeded";
  episode.termination_reason = "goal_reached";
  episode.ticks = ticks;
  episode.sim_time = ticks / 60.0;
  for (int m = 0; m < metrics; ++m) {
    if (m + 1 == metrics) {
      episode.metrics.push_back({"metric_" + std::to_string(m), std::nullopt, std::string("no humans")});
    } else {
      episode.metrics.push_back({"metric_" + std::to_string(m), index + m * 0.25, std::nullopt});
    }
  }
  for (int e = 0; e < events; ++e) {
    episode.events.push_back({e * 10, e * 10 / 60.0, "collision", "human_" + std::to_string(e), {{"part", "leg"}}});
  }
  for (int a = 0; a < agents; ++a) {
    for (int t = 0; t < ticks; ++t) {
      episode.trajectory.push_back({"agent_" + std::to_string(a), t, 0.01 * t + a, 0.5 * a, 0.001 * t});
    }
  }
  return episode;
}

}  // namespace hrisim::testing
