#pragma once
// Seeded random numbers that are the same on every platform: xoshiro256** seeded through SplitMix64,
// and the project's own distributions (the standard library's differ between implementations).
// A session owns one Random; each subsystem draws from its own named sub-stream, so adding draws in
// one subsystem does not shift the numbers another one sees.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace hrisim::core {

class Random {
 public:
  explicit Random(std::uint64_t seed = 0);

  /// An independent generator for a subsystem, derived from this one's seed and the name.
  Random stream(std::string_view subsystem) const;

  std::uint64_t next_u64();
  /// Uniform in [0, 1) with 53 random bits.
  double uniform();
  /// Uniform in [low, high).
  double uniform(double low, double high);
  /// Normal with the given mean and standard deviation (the ziggurat method: exact, and mostly one
  /// draw and one multiplication).
  double normal(double mean, double stddev);
  double standard_normal();

  std::uint64_t seed() const { return seed_; }
  /// The generator's whole state, for state hashes.
  const std::array<std::uint64_t, 4>& state() const { return state_; }

 private:
  std::uint64_t seed_;
  std::array<std::uint64_t, 4> state_{};
};

/// `prefix` and 128 bits from the operating system's random source, in hex: ids of uploaded
/// scenarios, sessions, runs and episodes, which nobody can guess. Never used inside a simulation.
std::string unguessable_id(char prefix);

/// FNV-1a 64-bit hash of bytes (stable across platforms), used for stream names and state hashes.
std::uint64_t fnv1a(std::string_view bytes, std::uint64_t hash = 0xcbf29ce484222325ULL);

}  // namespace hrisim::core
