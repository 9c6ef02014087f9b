#pragma once
// SHA-256 (FIPS 180-4), used to identify stored scenario sources by content.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace hrisim::core {

/// Incremental SHA-256.
class Sha256 {
 public:
  Sha256();
  void update(std::string_view data);
  /// Finishes the hash; the object must not be updated afterwards.
  std::array<std::uint8_t, 32> digest();

 private:
  void compress(const std::uint8_t* block);

  std::array<std::uint32_t, 8> state_;
  std::array<std::uint8_t, 64> buffer_{};
  std::size_t buffered_ = 0;
  std::uint64_t total_bytes_ = 0;
};

/// Lower-case hex of a digest.
std::string to_hex(const std::array<std::uint8_t, 32>& digest);

/// Lower-case hex SHA-256 of data.
std::string sha256_hex(std::string_view data);

}  // namespace hrisim::core
