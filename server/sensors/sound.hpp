#pragma once
// Sound in the building: sources (a person's speech, footsteps, doors, the elevator's bell, clips from
// WAV files, a robot's motors) and their propagation to a listening point — inverse-distance
// attenuation, the delay of the distance at the speed of sound, and a fixed attenuation per wall
// crossed. No reflections (so no reverberation), no diffraction round walls or through open doors,
// no frequency dependence of walls or air.
// A source is a pure function of the time since it began, evaluable at any fractional time: every
// microphone gets its own exact delay without buffers, and the same inputs give the same bits. Noise
// inside a source is a counter-based hash of (seed, sample index), not a stateful generator.
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "core/state_hash.hpp"
#include "sensors/wav.hpp"

namespace hrisim::sensors {

using Vec3 = Eigen::Vector3d;

/// Hz: the microphones' sample rate, the 16 kHz (what speech recognisers take).
inline constexpr double kSampleRate = 16000.0;
/// m/s: air at 20 °C.
inline constexpr double kSpeedOfSound = 343.0;
/// m: levels are given at this distance from a source, as sound levels are usually quoted.
inline constexpr double kReferenceDistance = 1.0;
/// m: nearer than this the gain stops growing: a mouth, a foot or a door is no point source closer
/// than about its own size.
inline constexpr double kMinDistance = 0.1;
/// Pressure gain per wall crossed, 10^(-33/20): 33 dB, the sound transmission class of the typical
/// interior wall — single wood studs, one layer of 1/2" gypsum board each side, no insulation
/// (Wikipedia, "Sound transmission class", partition table; the same STC 33 in Bliss, "Best Practices
/// Guide to Residential Construction", table 5-15). STC rates speech frequencies; walls let lower
/// ones through more, which this one number leaves out.
inline constexpr double kWallAttenuation = 0.022387211385683396;

// Levels: RMS sound pressure at kReferenceDistance over the sound's length, Pa (0 dB SPL = 20 µPa).
/// 60 dB SPL, a normal voice at 1 m (ANSI S3.5-1997's "normal" vocal effort is 62.35 dB; Pearsons,
/// Bennett and Fidell 1977 measured about 55–60 dB(A) for normal speech at 1 m).
inline constexpr double kSpeechLevel = 0.02;
/// 50 dB SPL over the 80 ms of a step: hrisim's estimate for shoes on a hard floor, heard at 1 m
/// about as loud as quiet speech.
inline constexpr double kFootstepLevel = 0.0063245553203367588;
/// 70 dB SPL over the 0.4 s of the sound: hrisim's estimate for a door closed normally (a slammed
/// door reaches 80–90 dB).
inline constexpr double kDoorLevel = 0.063245553203367588;
/// 70 dB SPL over the chime: within the ADA Standards' range for an elevator's hall signal (407.2.2.3:
/// 10 dB above ambient at least, 80 dB at most, at the hall call button, 1500 Hz at most).
inline constexpr double kBellLevel = 0.063245553203367588;

/// Steps per second at kStepRateSpeed: adults walking at their own pace (about 1.3 m/s) take about
/// 100–120 steps a minute.
inline constexpr double kStepRate = 2.0;
inline constexpr double kStepRateSpeed = 1.3;  ///< m/s
/// m/s: slower than this a person shifts their feet rather than walks; no footsteps are heard.
inline constexpr double kMinStepSpeed = 0.1;

enum class SoundKind { speech, footstep, door, bell, clip, motor };

/// What a source emits: the sound pressure at kReferenceDistance as a function of its age (time since
/// its start). Its position is the caller's to move, once per tick.
class SoundSource {
 public:
  /// A person saying something for `duration` s. `voice` picks the voice (fundamental 100–250 Hz,
  /// formants, syllable rate 4–5 Hz): the same seed, the same voice; `utterance` picks the syllables'
  /// loudness and consonants. A harmonic series (up to 6 kHz) shaped by three formants, under a
  /// syllable envelope, with consonant bursts and breath noise: broadband, as GCC-PHAT needs.
  static SoundSource speech(std::uint64_t voice, std::uint64_t utterance, double start, double duration,
                            double level = kSpeechLevel);
  /// One footfall: an 80 ms broadband burst and a low thud. footfalls() says when they fall.
  static SoundSource footstep(std::uint64_t seed, double start, double level = kFootstepLevel);
  /// A door shutting: a 50 Hz thump and the latch's click, 0.4 s.
  static SoundSource door(std::uint64_t seed, double start, double level = kDoorLevel);
  /// The elevator's chime: 660 Hz then 550 Hz, decaying, `chimes` times 1.2 s apart (the ADA signal:
  /// once for up, twice for down).
  static SoundSource bell(double start, int chimes = 1, double level = kBellLevel);
  /// A recorded clip (not null; any sample rate, interpolated Catmull–Rom between its samples — resample
  /// clips above kSampleRate first, or they alias), scaled to `level` RMS over its length.
  static SoundSource clip(std::shared_ptr<const AudioClip> clip, double start, double level = kSpeechLevel);
  /// A robot's motors: noise below about 1 kHz, from time 0 on and never ending; set_level() each tick.
  static SoundSource motor(std::uint64_t seed, double level);

  SoundKind kind() const { return kind_; }
  double start() const { return start_; }
  /// When it falls silent at the source; +infinity for motors. A listener d away hears it until
  /// end() + d / kSpeedOfSound: the caller may drop it after that.
  double end() const { return start_ + length_; }
  double level() const { return level_; }
  void set_level(double level);

  /// Sound pressure at kReferenceDistance, Pa, `age` s after the start; 0 before it and from the end on.
  double pressure(double age) const;

  void hash(core::StateHasher& hasher) const;

  Vec3 position = Vec3::Zero();  ///< map frame, z up from the floor, m

 private:
  SoundSource(SoundKind kind, std::uint64_t seed, double start, double length);
  double shape(double age) const;  ///< the unscaled waveform
  double speech_shape(double age) const;
  double clip_shape(double age) const;
  /// Scales the waveform to the level: RMS over the length sampled at kSampleRate.
  void calibrate();

  SoundKind kind_;
  std::uint64_t seed_;
  double start_, length_;
  double level_ = 0.0;
  double shape_rms_ = 1.0;  ///< RMS of shape() over the length
  double scale_ = 0.0;      ///< level_ / shape_rms_
  // speech
  std::uint64_t utterance_ = 0;
  double f0_ = 0.0, pitch_phase_ = 0.0, syllable_length_ = 0.0;
  int syllables_ = 0;
  std::vector<double> harmonics_, harmonic_phases_;
  // bell
  int chimes_ = 0;
  // clip
  std::shared_ptr<const AudioClip> clip_;
};

/// Walls crossed on the straight line from a source to a listener (the map's walls, closed doors).
using WallCount = std::function<int(const Vec3& source, const Vec3& listener)>;

/// Adds to `out` the sound pressure, Pa, at `listener` of every source, for the simulation's samples
/// [first_sample, first_sample + out.size()) (sample k at time k / kSampleRate): each source's
/// pressure d / kSpeedOfSound earlier, times kReferenceDistance / max(d, kMinDistance) and
/// kWallAttenuation to the power of its wall count in `walls` (one per source, or empty for none;
/// another count throws core::Error(internal)).
/// Positions are held for the block.
void propagate(std::span<const SoundSource> sources, std::span<const int> walls, const Vec3& listener,
               std::int64_t first_sample, std::span<float> out);

/// The first sample at or after `time`: a tick [t, t + dt) has the samples [sample_index(t),
/// sample_index(t + dt)), so consecutive ticks' blocks join without gap or overlap (when the caller
/// computes a tick's end and the next one's start alike).
std::int64_t sample_index(double time);

/// Steps per second of a person walking at `speed`: kStepRate at kStepRateSpeed, scaled with √speed
/// (hrisim's simplification: slower walkers shorten their steps and slow their cadence about
/// equally); 0 below kMinStepSpeed.
double step_rate(double speed);

/// Advances a walker's step phase (in steps, kept by the caller from tick to tick) over the tick
/// [time, time + dt) at `speed`, and appends the time of every footfall in it to `times`: the caller
/// then adds a footstep() at each, at the person's feet.
void footfalls(double& phase, double speed, double time, double dt, std::vector<double>& times);

}  // namespace hrisim::sensors
