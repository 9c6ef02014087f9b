#pragma once
// Records what a session's metrics need — the robot under test and every human at every step, and
// the events — as a metrics::Recording. The robot under test is the scenario's first robot.
#include <cstddef>
#include <optional>

#include "metrics/recording.hpp"
#include "sim/session.hpp"

namespace hrisim::sim {

class EpisodeRecorder {
 public:
  /// Records the session's current state as the first sample. With `max_bodies`, recording stops
  /// once the samples hold that many bodies (people plus robot), so a session that runs for hours
  /// keeps bounded memory; its metrics then cover the steps up to recorded_until().
  explicit EpisodeRecorder(const Session& session, std::optional<std::size_t> max_bodies = std::nullopt);
  /// Adds a sample of the session's state after a step (a tick already recorded is skipped).
  void record(const Session& session);
  /// The last tick recorded.
  std::int64_t recorded_until() const { return recording_.samples.back().tick; }
  /// The recording with the session's events, completion and `termination` (the session's own when empty).
  metrics::Recording finish(const Session& session, std::string termination = "") const;

 private:
  int robot_ = -1;  ///< agent index of the robot under test, -1 without one
  std::optional<std::size_t> max_bodies_;
  std::size_t bodies_ = 0;  ///< in the samples so far
  metrics::Recording recording_;
};

}  // namespace hrisim::sim
