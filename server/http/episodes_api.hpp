#pragma once
// Stored episodes over REST: an episode with its events, its series and trajectory (JSON or CSV), and
// videos of it filmed on the server (a job with its progress, then the file). Also the one way an
// episode is played again, for replay sessions and videos alike.
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "http/router.hpp"
#include "http/scenario_catalogue.hpp"
#include "runs/spec.hpp"

namespace hrisim::http {

class VideoJobs;

/// The episode as `caller` may see it: one of another owner's run is absent (404, with `pointer` in
/// its details when one is given).
storage::EpisodeRecord find_episode(storage::Store& store, const std::string& id, const Caller& caller, const std::string& pointer = "");

/// An episode in lists and replies: its facts and metrics.
nlohmann::json episode_json(const storage::EpisodeRecord& episode);

/// A stored episode to be played again: its scenario record, seed, and its run's controller, time
/// limit and scripted requests; played to its end it reaches the episode's state hash.
struct EpisodeReplay {
  storage::EpisodeRecord episode;
  nlohmann::json config;  ///< its run's (empty for an episode without a run)
  runs::RunRequest request;
  runs::RunSpec spec;
  std::string scenario_sha256;  ///< of its scenario as this server has it
};
/// 404 as find_episode; 409 when its scenario no longer loads.
EpisodeReplay replay_of_episode(storage::Store& store, ScenarioCatalogue& catalogue, const std::string& id, const Caller& caller,
                                const std::string& pointer = "");

void add_episode_routes(Router& router, std::shared_ptr<ScenarioCatalogue> catalogue, storage::Store* store, std::shared_ptr<VideoJobs> videos);

}  // namespace hrisim::http
