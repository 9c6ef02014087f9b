#pragma once
// What one request to a live session may ask for, and what the server's recordings may hold (named
// defaults, docs/limits.md); how many sessions a server holds is live::SessionLimits.
#include <cstddef>
#include <cstdint>

#include "live/limits.hpp"

namespace hrisim::http {

/// Most steps one step request may ask for.
inline constexpr int kMaxStepsPerRequest = 100000;
/// Sessions one step_many may step at once.
inline constexpr std::size_t kMaxSessionsPerStepMany = 1024;
/// Bytes the recordings of every live session and every run's episodes in flight may hold together
/// (metrics samples and trajectories); a session's recording then stops, a run's episode ends in error.
inline constexpr std::size_t kDefaultMaxRecordingBytes = std::size_t{1024} << 20;
/// Largest seed accepted: integers JSON numbers hold exactly.
inline constexpr std::int64_t kMaxSeed = (std::int64_t{1} << 53) - 1;

}  // namespace hrisim::http
