#pragma once
// Reading numbers back out of the bytes a protocol writer produced (little-endian, as the machines
// these tests run on and the protocols they check are).
#include <cstddef>
#include <cstring>
#include <string>

namespace hrisim::testing {

/// The number whose bytes start `at` bytes into `bytes`.
template <typename Number>
Number read_at(const std::string& bytes, std::size_t at) {
  Number value;
  std::memcpy(&value, bytes.data() + at, sizeof value);
  return value;
}

}  // namespace hrisim::testing
