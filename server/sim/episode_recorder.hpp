#pragma once
// Records what a session's metrics need — the robot under test and every human at every step, and
// the events — as a metrics::Recording. The robot under test is the scenario's first robot.
#include <cstddef>
#include <optional>
#include <string>

#include "core/memory_budget.hpp"
#include "metrics/packed_samples.hpp"
#include "metrics/recording.hpp"
#include "sim/session.hpp"

namespace hrisim::sim {

/// How much one recording may hold; recording stops at the first limit reached, so a session that runs
/// for hours keeps bounded memory, and its metrics cover the steps up to recorded_until(). The samples
/// are kept packed (metrics::PackedSamples) and unpacked, exactly, by finish().
struct RecorderLimits {
  std::optional<std::size_t> max_bodies;  ///< bodies (people plus robot) summed over the samples
  core::MemoryBudget* memory = nullptr;   ///< shared with other recordings; its bytes are estimated per sample
};

/// Why a recording stopped when `memory` was spent.
std::string recording_memory_spent(const core::MemoryBudget& memory);

class EpisodeRecorder {
 public:
  /// Records the session's current state as the first sample (even beyond the limits: there is always one).
  explicit EpisodeRecorder(const Session& session, RecorderLimits limits = {});
  /// Adds a sample of the session's state after a tick (a tick already recorded is skipped), with the
  /// benchmark task's rewards summed so far.
  void record(const Session& session, double reward = 0.0);
  /// Forgets the samples after `tick`: the recording of an episode gone back to that tick, which up to
  /// there is this one's bit for bit. Recording goes on from there (unless it had stopped before it).
  void forget_after(std::int64_t tick);
  /// The last tick recorded.
  std::int64_t recorded_until() const { return samples_.back().tick; }
  /// Why recording stopped before the session's last tick; empty while it goes on.
  const std::string& stopped() const { return stopped_; }
  /// The recording with the session's events, completion and `termination` (the session's own when empty).
  metrics::Recording finish(const Session& session, std::string termination = "") const;

 private:
  int robot_ = -1;  ///< agent index of the robot under test, -1 without one
  std::optional<std::size_t> max_bodies_;
  std::size_t bodies_ = 0;  ///< in the samples so far
  core::MemoryBudget::Lease memory_;
  std::string stopped_;
  metrics::Recording recording_;  ///< all but the samples
  metrics::PackedSamples samples_;
};

}  // namespace hrisim::sim
