#pragma once
// How many live sessions a server holds and how long they may idle (named defaults, README).
#include <chrono>
#include <cstdint>

namespace hrisim::http {

/// Live sessions a server holds at most; one more gets 503.
inline constexpr int kDefaultMaxSessions = 8;
/// A session nobody has used for this long is deleted.
inline constexpr std::chrono::seconds kDefaultSessionIdleTimeout{600};
/// Most steps one step request may ask for.
inline constexpr int kMaxStepsPerRequest = 100000;
/// Retry-After of a 503 for too many sessions, s.
inline constexpr int kSessionRetryAfter = 10;
/// Largest seed accepted: integers JSON numbers hold exactly.
inline constexpr std::int64_t kMaxSeed = (std::int64_t{1} << 53) - 1;

struct SessionLimits {
  int max_sessions = kDefaultMaxSessions;
  std::chrono::seconds idle_timeout = kDefaultSessionIdleTimeout;
};

}  // namespace hrisim::http
