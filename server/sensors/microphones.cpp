#include "sensors/microphones.hpp"

#include <algorithm>
#include <string>

#include "core/error.hpp"

namespace hrisim::sensors {

Vec3 MicrophoneArray::centre() const {
  Vec3 sum = Vec3::Zero();
  for (const Vec3& position : positions) sum += position;
  return positions.empty() ? sum : Vec3(sum / static_cast<double>(positions.size()));
}

std::optional<MicrophoneArray> microphone_array(const robots::RobotDescription& robot) {
  MicrophoneArray array;
  for (const robots::Sensor& mount : robot.sensors) {
    if (mount.type != "microphone") continue;
    if (array.link.empty()) array.link = mount.link;
    if (mount.link != array.link) {
      throw core::Error(core::ErrorCode::bad_request, "robot '" + robot.name + "': microphone '" + mount.name + "' is on " + mount.link +
                                                          ", the array's others on " + array.link + ": an array is on one link");
    }
    array.positions.emplace_back(mount.origin.x, mount.origin.y, mount.origin.z);
  }
  if (array.positions.empty()) return std::nullopt;
  return array;
}

std::span<const float> AudioBlock::channel(int c) const {
  return std::span<const float>(data).subspan(static_cast<std::size_t>(c) * static_cast<std::size_t>(samples), static_cast<std::size_t>(samples));
}

std::span<float> AudioBlock::channel(int c) {
  return std::span<float>(data).subspan(static_cast<std::size_t>(c) * static_cast<std::size_t>(samples), static_cast<std::size_t>(samples));
}

Microphones::Microphones(MicrophoneArray array, MicrophonesParams params) : array_(std::move(array)), params_(params) {}

void Microphones::record(std::span<const SoundSource> sources, const WallCount& walls, const Eigen::Isometry3d& link_pose,
                         std::int64_t first_sample, int count, const MotorNoise& motors, core::Random& random,
                         AudioBlock& block) const {
  block.first_sample = first_sample;
  block.channels = channels();
  block.samples = std::max(count, 0);
  block.data.assign(static_cast<std::size_t>(block.channels) * static_cast<std::size_t>(block.samples), 0.0f);
  const Vec3 centre = link_pose * array_.centre();
  walls_.clear();
  if (walls) {
    for (const SoundSource& source : sources) walls_.push_back(walls(source.position, centre));
  }
  // The motors are a source like any other, placed so that the array's centre hears them at the set level.
  SoundSource motor = SoundSource::motor(core::fnv1a("motors", random.seed()), 0.0);
  motor.position = motors.position;
  motor.set_level(params_.motor_noise * std::max(motors.load, 0.0) * std::max((motors.position - centre).norm(), kMinDistance) /
                  kReferenceDistance);
  for (int c = 0; c < block.channels; ++c) {
    const Vec3 microphone = link_pose * array_.positions[static_cast<std::size_t>(c)];
    const std::span<float> samples = block.channel(c);
    propagate(sources, walls_, microphone, first_sample, samples);
    if (motor.level() > 0.0) propagate(std::span(&motor, 1), {}, microphone, first_sample, samples);
    for (float& sample : samples) sample += static_cast<float>(random.normal(0.0, params_.self_noise));
  }
}

AudioHistory::AudioHistory(int channels, int window)
    : channels_(channels), window_(window), samples_(static_cast<std::size_t>(channels) * static_cast<std::size_t>(window), 0.0f) {}

std::span<const float> AudioHistory::channel(int c) const {
  return std::span<const float>(samples_).subspan(static_cast<std::size_t>(c) * static_cast<std::size_t>(window_), static_cast<std::size_t>(window_));
}

void AudioHistory::add(const AudioBlock& block) {
  if (block.channels != channels_) {
    throw core::Error(core::ErrorCode::internal, "an audio block of " + std::to_string(block.channels) +
                                                     " channels for a history of " + std::to_string(channels_));
  }
  const auto window = static_cast<std::ptrdiff_t>(window_);
  const auto fresh = std::min<std::ptrdiff_t>(block.samples, window);
  for (int c = 0; c < channels_; ++c) {
    const auto begin = samples_.begin() + c * window;
    std::copy(begin + fresh, begin + window, begin);  // the oldest `fresh` samples go
    const std::span<const float> incoming = block.channel(c).last(static_cast<std::size_t>(fresh));
    std::copy(incoming.begin(), incoming.end(), begin + (window - fresh));
  }
}

}  // namespace hrisim::sensors
