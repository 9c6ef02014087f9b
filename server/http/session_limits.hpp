#pragma once
// How many live sessions a server holds, how long they may idle and how much they record (named defaults, docs/limits.md).
#include <chrono>
#include <cstddef>
#include <cstdint>

namespace hrisim::core {
class MemoryBudget;
}

namespace hrisim::http {

/// Live sessions a server holds at most; one more gets 503.
inline constexpr int kDefaultMaxSessions = 8;
/// A session nobody has used for this long is deleted.
inline constexpr std::chrono::seconds kDefaultSessionIdleTimeout{600};
/// Most steps one step request may ask for.
inline constexpr int kMaxStepsPerRequest = 100000;
/// Sessions one step_many may step at once.
inline constexpr std::size_t kMaxSessionsPerStepMany = 1024;
/// Retry-After of a 503 for too many sessions, s.
inline constexpr int kSessionRetryAfter = 10;
/// Bytes the recordings of every live session and every run's episodes in flight may hold together
/// (metrics samples and trajectories); a session's recording then stops, a run's episode ends in error.
inline constexpr std::size_t kDefaultMaxRecordingBytes = std::size_t{1024} << 20;
/// Largest seed accepted: integers JSON numbers hold exactly.
inline constexpr std::int64_t kMaxSeed = (std::int64_t{1} << 53) - 1;

struct SessionLimits {
  int max_sessions = kDefaultMaxSessions;
  std::chrono::seconds idle_timeout = kDefaultSessionIdleTimeout;
  /// Shared with the runs' executor; none: unbounded. Must outlive the sessions.
  core::MemoryBudget* recording_memory = nullptr;
  /// Threads (the session's worker included) that compute each live session's crowd; any count gives
  /// the same trajectory. More than one helps crowds of hundreds on an otherwise idle machine.
  unsigned crowd_threads = 1;
};

}  // namespace hrisim::http
