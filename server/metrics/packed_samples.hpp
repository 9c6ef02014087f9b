#pragma once
// A recording's samples kept compact and exact: each sample is written as its difference from the one
// before — a double as the bytes of its bit pattern XOR the previous value's that are not zero, the
// tick as its step, the groups only when they change — into blocks of fixed size, so memory grows by
// what a sample holds and not by a container's doubling. Unpacked, every value is bit for bit what
// was packed.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "metrics/recording.hpp"

namespace hrisim::metrics {

class PackedSamples {
 public:
  /// Bytes a block holds (a sample larger than that gets a block of its own).
  static constexpr std::size_t kBlockBytes = 64 * 1024;

  void append(const Sample& sample);
  /// Every sample appended, in order, as it was.
  std::vector<Sample> unpack() const;
  /// Forgets the samples after `tick` (ticks grow from sample to sample), as if they had never been
  /// appended; `kept` sees each sample kept, in order.
  void keep_until(std::int64_t tick, const std::function<void(const Sample&)>& kept);

  std::size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  /// The last sample appended (undefined when empty).
  const Sample& back() const { return last_; }
  /// Memory held: the blocks' capacity and the last sample kept to difference the next against.
  std::size_t bytes() const;

 private:
  std::vector<std::vector<std::uint8_t>> blocks_;
  std::size_t count_ = 0;
  Sample last_;  ///< what the next sample is written against
};

}  // namespace hrisim::metrics
