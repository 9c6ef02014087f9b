#pragma once
// How many live sessions a server holds, how long they may idle and how much they record (named
// defaults, docs/limits.md).
#include <chrono>
#include <cstddef>

namespace hrisim::core {
class MemoryBudget;
}

namespace hrisim::live {

/// Live sessions a server holds at most; one more is refused (unavailable).
inline constexpr int kDefaultMaxSessions = 8;
/// A session nobody has used for this long is deleted.
inline constexpr std::chrono::seconds kDefaultSessionIdleTimeout{600};
/// How long a client refused for too many sessions should wait before it asks again, s.
inline constexpr int kSessionRetryAfter = 10;

struct SessionLimits {
  int max_sessions = kDefaultMaxSessions;
  std::chrono::seconds idle_timeout = kDefaultSessionIdleTimeout;
  /// Shared with the runs' executor; none: unbounded. Must outlive the sessions.
  core::MemoryBudget* recording_memory = nullptr;
  /// Threads (the session's worker included) that compute each live session's crowd; any count gives
  /// the same trajectory. More than one helps crowds of hundreds on an otherwise idle machine.
  unsigned crowd_threads = 1;
};

}  // namespace hrisim::live
