#pragma once
// Microphone arrays as robot sensors: the sound of the sources propagated to each microphone of an
// array on a robot's link, plus each microphone's own noise and the robot's motors, in blocks of
// float32 samples at kSampleRate, one block per tick. An AudioHistory keeps the last few ticks for
// the direction of arrival (sound_direction.hpp).
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "core/random.hpp"
#include "robots/description.hpp"
#include "sensors/sound.hpp"

namespace hrisim::sensors {

/// Pa RMS, white, independent per channel: 30 dB SPL, the self-noise of a MEMS microphone with the
/// common 65 dB(A) signal-to-noise ratio at 94 dB SPL (about 29 dB(A)).
inline constexpr double kSelfNoise = 6.324555320336759e-4;
/// Pa RMS at the array's centre with the motors at full speed: 50 dB SPL, hrisim's estimate — a robot's
/// ego-noise at its own head is of the order of quiet speech at 1 m.
inline constexpr double kMotorNoiseLevel = 0.0063245553203367588;

struct MicrophoneArray {
  std::string link;             ///< the link it is mounted on
  std::vector<Vec3> positions;  ///< channel i's microphone in the link's frame, m

  Vec3 centre() const;
};

/// The array of a robot's microphone mounts (type "microphone" in its description), in description
/// order; none without. They must share one link (core::Error(bad_request) otherwise). ROMAN's six are
/// on its head (seed 000 says only that it has six: the arrangement is hrisim's); the HSR's four on a
/// 0.05 m circle at the head's top (hrisim's: the HSR's array geometry is not published — its URDF,
/// hsrb_description, has no microphone link).
std::optional<MicrophoneArray> microphone_array(const robots::RobotDescription& robot);

struct MicrophonesParams {
  double self_noise = kSelfNoise;   ///< Pa RMS per channel
  double motor_noise = kMotorNoiseLevel;  ///< Pa RMS at the array's centre at full motor load
};

/// A tick's audio: sound pressure in Pa as float32, planar — channel c's samples are
/// data[c × samples, (c + 1) × samples) — for the simulation's samples [first_sample, first_sample + samples).
struct AudioBlock {
  std::int64_t first_sample = 0;
  int channels = 0;
  int samples = 0;
  std::vector<float> data;

  std::span<const float> channel(int c) const;
  std::span<float> channel(int c);
};

/// The robot's own motors, heard at its array as a source at `position` (map frame, e.g. the drive
/// under the body) whose level at the array's centre is MicrophonesParams::motor_noise × load.
struct MotorNoise {
  Vec3 position = Vec3::Zero();
  double load = 0.0;  ///< 0 when still … 1 at full speed (e.g. |wheel speed| / its limit)
};

class Microphones {
 public:
  explicit Microphones(MicrophoneArray array, MicrophonesParams params = {});
  const MicrophoneArray& array() const { return array_; }
  const MicrophonesParams& params() const { return params_; }
  int channels() const { return static_cast<int>(array_.positions.size()); }

  /// Records the samples [first_sample, first_sample + count) with the array's link at `link_pose`
  /// (map frame): every source propagated to every microphone, the walls counted once per source to
  /// the array's centre; then the motors (seeded from `random`'s seed) and the self-noise (drawn from
  /// `random`, channels × count normal draws whatever is heard).
  void record(std::span<const SoundSource> sources, const WallCount& walls, const Eigen::Isometry3d& link_pose,
              std::int64_t first_sample, int count, const MotorNoise& motors, core::Random& random,
              AudioBlock& block) const;

 private:
  MicrophoneArray array_;
  MicrophonesParams params_;
  mutable std::vector<int> walls_;  ///< scratch of record: per source
};

/// The last `window` samples of every channel, planar (channel c at [c × window, (c + 1) × window)),
/// oldest first, zeros before the first block: what DirectionOfArrival::estimate reads.
class AudioHistory {
 public:
  AudioHistory(int channels, int window);
  /// Appends a block of as many channels, dropping the oldest samples.
  void add(const AudioBlock& block);
  std::span<const float> samples() const { return samples_; }
  std::span<const float> channel(int c) const;
  int channels() const { return channels_; }
  int window() const { return window_; }

 private:
  int channels_, window_;
  std::vector<float> samples_;
};

}  // namespace hrisim::sensors
