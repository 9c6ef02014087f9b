#pragma once
// Hash of a simulation state, fed field by field with the exact bits of every number, so that two
// runs agree on the hash exactly when they agree on the state bit for bit.
#include <bit>
#include <cstdint>
#include <string_view>

#include "core/random.hpp"

namespace hrisim::core {

class StateHasher {
 public:
  StateHasher& add(std::uint64_t value) {
    for (int i = 0; i < 8; ++i) {
      hash_ ^= (value >> (8 * i)) & 0xff;
      hash_ *= 0x100000001b3ULL;
    }
    return *this;
  }
  StateHasher& add(std::int64_t value) { return add(std::bit_cast<std::uint64_t>(value)); }
  StateHasher& add(int value) { return add(static_cast<std::int64_t>(value)); }
  StateHasher& add(bool value) { return add(std::uint64_t{value}); }
  StateHasher& add(double value) { return add(std::bit_cast<std::uint64_t>(value)); }
  StateHasher& add(std::string_view text) {
    hash_ = fnv1a(text, hash_);
    return add(static_cast<std::uint64_t>(text.size()));
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

}  // namespace hrisim::core
