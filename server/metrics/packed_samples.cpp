#include "metrics/packed_samples.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <string>

namespace hrisim::metrics {
namespace {

constexpr int kBodyValues = 6;  // position x, y, velocity x, y, heading, radius

std::array<double, kBodyValues> values_of(const Body& body) {
  return {body.position.x(), body.position.y(), body.velocity.x(), body.velocity.y(), body.heading, body.radius};
}

/// The body in `before` that a body of `agent` at `index` is written against: the same agent at the
/// same place, or anywhere; none (all zeros) for an agent that has just come.
Body reference_for(int agent, std::size_t index, const std::vector<Body>& before) {
  if (index < before.size() && before[index].agent == agent) return before[index];
  const auto found = std::find_if(before.begin(), before.end(), [&](const Body& b) { return b.agent == agent; });
  if (found != before.end()) return *found;
  Body none;
  none.agent = agent;
  return none;
}

class Writer {
 public:
  explicit Writer(std::vector<std::uint8_t>& out) : out_(out) {}

  void unsigned_number(std::uint64_t value) {
    while (value >= 0x80) {
      out_.push_back(static_cast<std::uint8_t>(value | 0x80));
      value >>= 7;
    }
    out_.push_back(static_cast<std::uint8_t>(value));
  }
  void signed_number(std::int64_t value) {
    unsigned_number((static_cast<std::uint64_t>(value) << 1) ^ static_cast<std::uint64_t>(value >> 63));
  }
  void byte(std::uint8_t value) { out_.push_back(value); }

  /// Each value as the low bytes of its bits XOR the previous value's bits that are not all zero above
  /// them; the byte counts two to a byte.
  void doubles(const double* now, const double* before, int count) {
    for (int i = 0; i < count; i += 2) {
      const std::uint64_t first = difference(now[i], before[i]);
      const std::uint64_t second = i + 1 < count ? difference(now[i + 1], before[i + 1]) : 0;
      const int first_bytes = significant_bytes(first), second_bytes = significant_bytes(second);
      out_.push_back(static_cast<std::uint8_t>(first_bytes | (second_bytes << 4)));
      low_bytes(first, first_bytes);
      low_bytes(second, second_bytes);
    }
  }

  void body(const Body& now, const Body& before) {
    signed_number(now.agent);
    byte(now.touching_robot ? 1 : 0);
    const auto a = values_of(now), b = values_of(before);
    doubles(a.data(), b.data(), kBodyValues);
  }

 private:
  static std::uint64_t difference(double now, double before) { return std::bit_cast<std::uint64_t>(now) ^ std::bit_cast<std::uint64_t>(before); }
  static int significant_bytes(std::uint64_t bits) { return (64 - std::countl_zero(bits) + 7) / 8; }
  void low_bytes(std::uint64_t bits, int count) {
    for (int k = 0; k < count; ++k) out_.push_back(static_cast<std::uint8_t>(bits >> (8 * k)));
  }

  std::vector<std::uint8_t>& out_;
};

class Reader {
 public:
  Reader(const std::uint8_t* at, const std::uint8_t* end) : at_(at), end_(end) {}
  bool done() const { return at_ >= end_; }
  const std::uint8_t* at() const { return at_; }

  std::uint64_t unsigned_number() {
    std::uint64_t value = 0;
    for (int shift = 0;; shift += 7) {
      const std::uint8_t b = *at_++;
      value |= static_cast<std::uint64_t>(b & 0x7F) << shift;
      if (!(b & 0x80)) return value;
    }
  }
  std::int64_t signed_number() {
    const std::uint64_t v = unsigned_number();
    return static_cast<std::int64_t>(v >> 1) ^ -static_cast<std::int64_t>(v & 1);
  }
  std::uint8_t byte() { return *at_++; }

  void doubles(double* now, const double* before, int count) {
    for (int i = 0; i < count; i += 2) {
      const std::uint8_t counts = *at_++;
      now[i] = undo(before[i], counts & 0x0F);
      if (i + 1 < count) now[i + 1] = undo(before[i + 1], counts >> 4);
    }
  }

  Body body(const Body& before) {
    Body now;
    now.agent = static_cast<int>(signed_number());
    now.touching_robot = byte() != 0;
    std::array<double, kBodyValues> values{};
    const auto b = values_of(before);
    doubles(values.data(), b.data(), kBodyValues);
    now.position = {values[0], values[1]};
    now.velocity = {values[2], values[3]};
    now.heading = values[4];
    now.radius = values[5];
    return now;
  }

 private:
  double undo(double before, int count) {
    std::uint64_t bits = 0;
    for (int k = 0; k < count; ++k) bits |= static_cast<std::uint64_t>(*at_++) << (8 * k);
    return std::bit_cast<double>(bits ^ std::bit_cast<std::uint64_t>(before));
  }

  const std::uint8_t* at_;
  const std::uint8_t* end_;
};

void write_sample(Writer& out, const Sample& now, const Sample& before) {
  out.signed_number(now.tick - before.tick);
  const double values[] = {now.reward, now.obstacle_distance}, previous[] = {before.reward, before.obstacle_distance};
  out.doubles(values, previous, 2);
  out.body(now.robot, before.robot);
  out.unsigned_number(now.humans.size());
  for (std::size_t i = 0; i < now.humans.size(); ++i) out.body(now.humans[i], reference_for(now.humans[i].agent, i, before.humans));
  out.unsigned_number(now.touched_obstacles.size());
  for (const std::string& name : now.touched_obstacles) {
    out.unsigned_number(name.size());
    for (const char c : name) out.byte(static_cast<std::uint8_t>(c));
  }
  // Groups change rarely: 0 when they are the previous sample's.
  if (now.groups == before.groups) {
    out.unsigned_number(0);
    return;
  }
  out.unsigned_number(now.groups.size() + 1);
  for (const std::vector<int>& group : now.groups) {
    out.unsigned_number(group.size());
    for (const int member : group) out.signed_number(member);
  }
}

Sample read_sample(Reader& in, const Sample& before) {
  Sample now;
  now.tick = before.tick + in.signed_number();
  const double previous[] = {before.reward, before.obstacle_distance};
  double values[2];
  in.doubles(values, previous, 2);
  now.reward = values[0];
  now.obstacle_distance = values[1];
  now.robot = in.body(before.robot);
  now.humans.resize(in.unsigned_number());
  for (std::size_t i = 0; i < now.humans.size(); ++i) {
    // The agent comes first, so the reference can be found before the values are read.
    Reader ahead = in;
    const int agent = static_cast<int>(ahead.signed_number());
    now.humans[i] = in.body(reference_for(agent, i, before.humans));
  }
  now.touched_obstacles.resize(in.unsigned_number());
  for (std::string& name : now.touched_obstacles) {
    name.resize(in.unsigned_number());
    for (char& c : name) c = static_cast<char>(in.byte());
  }
  const std::uint64_t groups = in.unsigned_number();
  if (groups == 0) {
    now.groups = before.groups;
    return now;
  }
  now.groups.resize(groups - 1);
  for (std::vector<int>& group : now.groups) {
    group.resize(in.unsigned_number());
    for (int& member : group) member = static_cast<int>(in.signed_number());
  }
  return now;
}

}  // namespace

void PackedSamples::append(const Sample& sample) {
  thread_local std::vector<std::uint8_t> encoded;
  encoded.clear();
  Writer writer(encoded);
  write_sample(writer, sample, last_);
  // A sample never straddles two blocks, so each block reads on its own from its first byte.
  if (blocks_.empty() || blocks_.back().size() + encoded.size() > blocks_.back().capacity()) {
    blocks_.emplace_back().reserve(std::max(kBlockBytes, encoded.size()));
  }
  blocks_.back().insert(blocks_.back().end(), encoded.begin(), encoded.end());
  last_ = sample;
  ++count_;
}

std::vector<Sample> PackedSamples::unpack() const {
  std::vector<Sample> samples;
  samples.reserve(count_);
  Sample before;
  for (const std::vector<std::uint8_t>& block : blocks_) {
    Reader reader(block.data(), block.data() + block.size());
    while (!reader.done()) {
      samples.push_back(read_sample(reader, before));
      before = samples.back();
    }
  }
  return samples;
}

void PackedSamples::keep_until(std::int64_t tick, const std::function<void(const Sample&)>& kept) {
  Sample before;
  std::size_t count = 0;
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    std::vector<std::uint8_t>& block = blocks_[b];
    Reader reader(block.data(), block.data() + block.size());
    while (!reader.done()) {
      const std::uint8_t* start = reader.at();
      Sample sample = read_sample(reader, before);
      if (sample.tick > tick) {
        block.resize(static_cast<std::size_t>(start - block.data()));
        blocks_.resize(block.empty() ? b : b + 1);
        last_ = std::move(before);
        count_ = count;
        return;
      }
      kept(sample);
      before = std::move(sample);
      ++count;
    }
  }
}

std::size_t PackedSamples::bytes() const {
  std::size_t bytes = sizeof(*this) + blocks_.capacity() * sizeof(blocks_[0]) + last_.humans.capacity() * sizeof(Body);
  for (const auto& block : blocks_) bytes += block.capacity();
  return bytes;
}

}  // namespace hrisim::metrics
