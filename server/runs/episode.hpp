#pragma once
// One headless episode: a session of a scenario with a seed, run to its end, with its metrics, events
// and every agent's trajectory sampled at kTrajectoryRate.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "storage/store.hpp"

namespace hrisim::core {
class MemoryBudget;
}
namespace hrisim::scenario {
struct Model;
}
namespace hrisim::sim {
class Session;
}

namespace hrisim::runs {

/// Trajectory samples per second of simulation time kept for every agent.
inline constexpr double kTrajectoryRate = 10.0;

/// Ticks between two trajectory samples at time step dt.
std::int64_t trajectory_stride(double dt);

struct EpisodeOptions {
  std::optional<double> max_time;  ///< s of simulation time; the scenario's limit when empty
  std::vector<std::pair<double, std::string>> requests;  ///< the robot asks for routine (second) at time (first)
  std::function<void(const sim::Session&)> observe;      ///< called at the start and after every step, read-only
  const std::atomic<bool>* cancel = nullptr;             ///< stops the episode at its next step when set
  /// Also runs the seed without the robots to measure human_path_deviation (twice the work).
  bool baseline_without_robot = false;
  /// Shared with every recording of the process; an episode whose recording (or trajectory) would pass
  /// it ends in error. None: unbounded.
  core::MemoryBudget* recording_memory = nullptr;
};

struct EpisodeResult {
  bool cancelled = false;
  nlohmann::json summary;  ///< what `hrisim run` prints for the episode
  /// Everything stored for it; the caller sets id, run, scenario and controller.
  storage::EpisodeRecord record;
};

/// Runs one episode; throws core::Error(bad_request) for a scripted request the scenario cannot make,
/// core::Error(unavailable) when the recording memory is spent.
EpisodeResult run_episode(const std::shared_ptr<const scenario::Model>& model, std::uint64_t seed, const EpisodeOptions& options);

}  // namespace hrisim::runs
