#pragma once
// Records what a session's metrics need — the robot under test and every human at every step, and
// the events — as a metrics::Recording. The robot under test is the scenario's first robot.
#include "metrics/recording.hpp"
#include "sim/session.hpp"

namespace hrisim::sim {

class EpisodeRecorder {
 public:
  /// Records the session's current state as the first sample.
  explicit EpisodeRecorder(const Session& session);
  /// Adds a sample of the session's state after a step (a tick already recorded is skipped).
  void record(const Session& session);
  /// The recording with the session's events, completion and `termination` (the session's own when empty).
  metrics::Recording finish(const Session& session, std::string termination = "") const;

 private:
  int robot_ = -1;  ///< agent index of the robot under test, -1 without one
  metrics::Recording recording_;
};

}  // namespace hrisim::sim
