#pragma once
// Hash of a simulation state, fed field by field with the exact bits of every number, so that two
// runs agree on the hash when they agree on the state bit for bit (and, but for a 2^-64 chance, only then).
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "core/random.hpp"

namespace hrisim::core {

class StateHasher {
 public:
  /// A whole word at a time: each step (xor, then SplitMix64's finaliser) is a bijection of the hash, so
  /// two sequences that differ in one word never hash alike, and a word costs a few multiplications.
  StateHasher& add(std::uint64_t value) {
    std::uint64_t z = hash_ ^ value;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    hash_ = z ^ (z >> 31);
    bytes_ += sizeof value;
    return *this;
  }
  StateHasher& add(std::int64_t value) { return add(std::bit_cast<std::uint64_t>(value)); }
  StateHasher& add(int value) { return add(static_cast<std::int64_t>(value)); }
  StateHasher& add(bool value) { return add(std::uint64_t{value}); }
  StateHasher& add(double value) { return add(std::bit_cast<std::uint64_t>(value)); }
  /// Many numbers at once (a laser scan): a multiplication and a rotation per word (still a bijection,
  /// so one differing word always shows; the rotation carries high bits down, so that differences in
  /// two words do not cancel), and the full mix once, with the count.
  StateHasher& add(std::span<const double> values) {
    std::uint64_t z = hash_;
    for (const double value : values) z = std::rotl((z ^ std::bit_cast<std::uint64_t>(value)) * 0x9e3779b97f4a7c15ULL, 27);
    hash_ = z;
    bytes_ += values.size_bytes();
    return add(static_cast<std::uint64_t>(values.size()));
  }
  StateHasher& add(std::string_view text) {
    hash_ = fnv1a(text, hash_);
    bytes_ += text.size();
    return add(static_cast<std::uint64_t>(text.size()));
  }
  std::uint64_t value() const { return hash_; }
  /// Bytes of data fed so far: how much a state holds, without its containers' own overhead.
  std::size_t bytes() const { return bytes_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
  std::size_t bytes_ = 0;
};

}  // namespace hrisim::core
