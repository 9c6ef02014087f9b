#include "sensors/sound.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "core/portable_math.hpp"

namespace hrisim::sensors {
namespace {

// Speech. Fundamentals: men speak at about 100–120 Hz, women at about 200–220 Hz (Titze, "Principles
// of voice production", 1994); conversational speech runs at about 4–5 syllables a second.
constexpr double kMinF0 = 100.0, kMaxF0 = 250.0;                 ///< Hz
constexpr double kMinSyllableRate = 4.0, kMaxSyllableRate = 5.0;  ///< Hz
/// Hz: the highest harmonic. Speech has energy up to 8 kHz and more; the ceiling stays clear of the
/// 8 kHz Nyquist frequency with the pitch's swing.
constexpr double kHarmonicCeiling = 6000.0;
/// Formant centres (Hz) are drawn per voice within these ranges (Peterson and Barney's vowels, 1952),
/// with these bandwidths (Hz) and peak gains over the glottal source's −6 dB/octave slope.
constexpr double kFormantLow[3] = {300.0, 900.0, 2300.0};
constexpr double kFormantHigh[3] = {800.0, 2300.0, 3000.0};
constexpr double kFormantBandwidth[3] = {80.0, 120.0, 160.0};
constexpr double kFormantGain[3] = {10.0, 6.0, 3.0};
/// The pitch swings by this share of the fundamental at kPitchRate: intonation, not a monotone.
constexpr double kPitchDepth = 0.08;
constexpr double kPitchRate = 0.8;  ///< Hz
/// Syllables' peak amplitudes are uniform in [kQuietestSyllable, 1].
constexpr double kQuietestSyllable = 0.4;
/// Share of syllables that begin with a consonant: a noise burst decaying as (1 - p)^8 over the
/// syllable (p its progress, about 25 ms), of amplitude kConsonant relative to the syllable's peak.
constexpr double kConsonantShare = 0.6;
constexpr double kConsonant = 1.0;
/// Breath noise under every syllable's envelope (not its peak), relative to a syllable's full amplitude.
constexpr double kBreath = 0.05;
/// Mean square of hash noise linearly interpolated between uniform [-1, 1) values: (1/3)(2/3).
constexpr double kGridNoiseMeanSquare = 2.0 / 9.0;

// Footstep, door, bell: lengths and decay times, s; frequencies, Hz. hrisim's choices, after the
// sounds' usual character (a short broadband tap over a low thud; a low thump and a click).
constexpr double kFootstepLength = 0.08, kFootstepDecay = 0.01, kThudFrequency = 80.0, kThudDecay = 0.03, kThud = 0.5;
constexpr double kDoorLength = 0.4, kDoorThumpFrequency = 50.0, kDoorThumpDecay = 0.08, kDoorClickDecay = 0.006, kDoorClick = 0.6;
/// The classic two-tone chime: "ding" at 660 Hz, "dong" at 550 Hz half a second later.
constexpr double kDing = 660.0, kDong = 550.0, kDongDelay = 0.5, kToneLength = 1.5, kToneDecay = 0.35, kChimeInterval = 1.2;
constexpr double kToneSecondHarmonic = 0.2;  ///< an electronic chime is nearly a pure tone
/// Hz: motor noise is hash noise on this grid, linearly interpolated: its energy lies below about 1 kHz.
constexpr double kMotorNoiseGrid = 2000.0;

std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// Uniform in [0, 1), a pure function of (seed, index).
double hash01(std::uint64_t seed, std::int64_t index) {
  const std::uint64_t z = mix(seed ^ mix(static_cast<std::uint64_t>(index) + 0x9e3779b97f4a7c15ULL));
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

/// White noise at `rate` Hz, linearly interpolated: continuous in t, so it can be delayed by any fraction of a sample.
double grid_noise(std::uint64_t seed, double t, double rate) {
  const double x = t * rate;
  const double n = std::floor(x);
  const double f = x - n;
  const auto index = static_cast<std::int64_t>(n);
  return (1.0 - f) * (2.0 * hash01(seed, index) - 1.0) + f * (2.0 * hash01(seed, index + 1) - 1.0);
}

/// e^(−t / time_constant), the same bits everywhere.
double decay(double t, double time_constant) { return core::exp_nonpositive(static_cast<float>(-t / time_constant)); }

/// A decaying chime tone, faded linearly to 0 at its end so that it stops without a click.
double tone(double t, double frequency) {
  if (t < 0.0 || t >= kToneLength) return 0.0;
  return (1.0 - t / kToneLength) * decay(t, kToneDecay) *
         (core::sin_turns(frequency * t) + kToneSecondHarmonic * core::sin_turns(2.0 * frequency * t));
}

}  // namespace

SoundSource::SoundSource(SoundKind kind, std::uint64_t seed, double start, double length)
    : kind_(kind), seed_(seed), start_(start), length_(length) {}

SoundSource SoundSource::speech(std::uint64_t voice, std::uint64_t utterance, double start, double duration, double level) {
  SoundSource source(SoundKind::speech, voice, start, std::max(duration, 0.0));
  source.utterance_ = mix(voice ^ mix(utterance));
  source.f0_ = kMinF0 + (kMaxF0 - kMinF0) * hash01(voice, 0);
  const double syllable_rate = kMinSyllableRate + (kMaxSyllableRate - kMinSyllableRate) * hash01(voice, 1);
  // A whole number of syllables, so that the envelope is back at 0 when the utterance ends.
  source.syllables_ = std::max(1, static_cast<int>(std::lround(source.length_ * syllable_rate)));
  source.syllable_length_ = source.length_ / source.syllables_;
  source.pitch_phase_ = hash01(source.utterance_, -1);
  double formants[3];
  for (int i = 0; i < 3; ++i) formants[i] = kFormantLow[i] + (kFormantHigh[i] - kFormantLow[i]) * hash01(voice, 2 + i);
  double mean_square = 0.0;
  for (int h = 1; h * source.f0_ <= kHarmonicCeiling; ++h) {
    double gain = 1.0;
    for (int i = 0; i < 3; ++i) {
      const double offset = (h * source.f0_ - formants[i]) / kFormantBandwidth[i];
      gain += kFormantGain[i] / (1.0 + offset * offset);
    }
    source.harmonics_.push_back(gain / h);
    source.harmonic_phases_.push_back(hash01(voice, 100 + h));
    mean_square += 0.5 * source.harmonics_.back() * source.harmonics_.back();
  }
  for (double& amplitude : source.harmonics_) amplitude /= std::sqrt(mean_square);  // the series' mean square is 1
  // The expected mean square over syllables (envelope A sin²: E[A²] × 3/8), calibrated without sampling.
  const double a = kQuietestSyllable;
  const double syllable_mean_square = (1.0 - a * a * a) / (3.0 * (1.0 - a));
  source.shape_rms_ = std::sqrt(syllable_mean_square * 3.0 / 8.0 +
                                kConsonantShare * kConsonant * kConsonant * syllable_mean_square / 17.0 * kGridNoiseMeanSquare +
                                kBreath * kBreath * 3.0 / 8.0 * kGridNoiseMeanSquare);
  source.set_level(level);
  return source;
}

SoundSource SoundSource::footstep(std::uint64_t seed, double start, double level) {
  SoundSource source(SoundKind::footstep, seed, start, kFootstepLength);
  source.level_ = level;
  source.calibrate();
  return source;
}

SoundSource SoundSource::door(std::uint64_t seed, double start, double level) {
  SoundSource source(SoundKind::door, seed, start, kDoorLength);
  source.level_ = level;
  source.calibrate();
  return source;
}

SoundSource SoundSource::bell(double start, int chimes, double level) {
  chimes = std::max(chimes, 1);
  SoundSource source(SoundKind::bell, 0, start, (chimes - 1) * kChimeInterval + kDongDelay + kToneLength);
  source.chimes_ = chimes;
  source.level_ = level;
  source.calibrate();
  return source;
}

SoundSource SoundSource::clip(std::shared_ptr<const AudioClip> clip, double start, double level) {
  SoundSource source(SoundKind::clip, 0, start, clip->duration());
  double sum = 0.0;
  for (const float sample : clip->samples) sum += static_cast<double>(sample) * sample;
  const double rms = clip->samples.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(clip->samples.size()));
  source.clip_ = std::move(clip);
  source.shape_rms_ = rms > 0.0 ? rms : 1.0;  // a silent clip stays silent at any level
  source.set_level(level);
  return source;
}

SoundSource SoundSource::motor(std::uint64_t seed, double level) {
  SoundSource source(SoundKind::motor, seed, 0.0, std::numeric_limits<double>::infinity());
  source.shape_rms_ = std::sqrt(kGridNoiseMeanSquare);
  source.set_level(level);
  return source;
}

void SoundSource::set_level(double level) {
  level_ = level;
  scale_ = level / shape_rms_;
}

void SoundSource::calibrate() {
  const auto samples = static_cast<int>(std::ceil(length_ * kSampleRate));
  double sum = 0.0;
  for (int k = 0; k < samples; ++k) {
    const double value = shape(k / kSampleRate);
    sum += value * value;
  }
  shape_rms_ = samples > 0 && sum > 0.0 ? std::sqrt(sum / samples) : 1.0;
  set_level(level_);
}

double SoundSource::pressure(double age) const {
  if (!(age >= 0.0 && age < length_)) return 0.0;
  return scale_ * shape(age);
}

double SoundSource::shape(double age) const {
  switch (kind_) {
    case SoundKind::speech: return speech_shape(age);
    case SoundKind::footstep:
      return (1.0 - age / kFootstepLength) * (grid_noise(seed_, age, kSampleRate) * decay(age, kFootstepDecay) +
                                              kThud * core::sin_turns(kThudFrequency * age) * decay(age, kThudDecay));
    case SoundKind::door:
      return (1.0 - age / kDoorLength) * (core::sin_turns(kDoorThumpFrequency * age) * decay(age, kDoorThumpDecay) +
                                          kDoorClick * grid_noise(seed_, age, kSampleRate) * decay(age, kDoorClickDecay));
    case SoundKind::bell: {
      double sum = 0.0;
      for (int chime = 0; chime < chimes_; ++chime) {
        const double t = age - chime * kChimeInterval;
        sum += tone(t, kDing) + tone(t - kDongDelay, kDong);
      }
      return sum;
    }
    case SoundKind::clip: return clip_shape(age);
    case SoundKind::motor: return grid_noise(seed_, age, kMotorNoiseGrid);
  }
  return 0.0;
}

double SoundSource::speech_shape(double age) const {
  const double position = age / syllable_length_;
  const int syllable = std::min(static_cast<int>(position), syllables_ - 1);
  const double p = position - syllable;  // progress through the syllable, 0…1
  const double peak = kQuietestSyllable + (1.0 - kQuietestSyllable) * hash01(utterance_, syllable);
  const double rise = core::sin_turns(0.5 * p);
  const double envelope = peak * rise * rise;
  // Cycles of the fundamental so far: the integral of f0 (1 + depth sin(2π (rate t + phase))).
  const double cycles = f0_ * (age - kPitchDepth / (2.0 * std::numbers::pi * kPitchRate) *
                                        (core::cos_turns(kPitchRate * age + pitch_phase_) - core::cos_turns(pitch_phase_)));
  double voiced = 0.0;
  for (std::size_t h = 0; h < harmonics_.size(); ++h) {
    voiced += harmonics_[h] * core::sin_turns(static_cast<double>(h + 1) * cycles + harmonic_phases_[h]);
  }
  double noise_amplitude = kBreath * rise * rise;
  if (hash01(utterance_, syllables_ + syllable) < kConsonantShare) {
    const double q = (1.0 - p) * (1.0 - p), q4 = q * q;
    noise_amplitude += kConsonant * peak * q4 * q4;
  }
  return envelope * voiced + noise_amplitude * grid_noise(seed_ ^ utterance_, age, kSampleRate);
}

double SoundSource::clip_shape(double age) const {
  const std::vector<float>& samples = clip_->samples;
  const double x = age * clip_->sample_rate;
  const double n = std::floor(x);
  const double f = x - n;
  const auto i = static_cast<std::ptrdiff_t>(n);
  const auto at = [&samples](std::ptrdiff_t k) {
    return k >= 0 && k < static_cast<std::ptrdiff_t>(samples.size()) ? static_cast<double>(samples[static_cast<std::size_t>(k)]) : 0.0;
  };
  const double p0 = at(i - 1), p1 = at(i), p2 = at(i + 1), p3 = at(i + 2);
  return p1 + 0.5 * f * (p2 - p0 + f * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3 + f * (3.0 * (p1 - p2) + p3 - p0)));
}

void SoundSource::hash(core::StateHasher& hasher) const {
  hasher.add(static_cast<int>(kind_)).add(seed_).add(utterance_).add(start_).add(length_).add(level_).add(chimes_);
  hasher.add(position.x()).add(position.y()).add(position.z());
}

void propagate(std::span<const SoundSource> sources, std::span<const int> walls, const Vec3& listener,
               std::int64_t first_sample, std::span<float> out) {
  if (!walls.empty() && walls.size() != sources.size()) {
    throw core::Error(core::ErrorCode::internal, "sound: " + std::to_string(walls.size()) + " wall counts for " +
                                                     std::to_string(sources.size()) + " sources");
  }
  const double block_start = static_cast<double>(first_sample) / kSampleRate;
  const double block_end = static_cast<double>(first_sample + static_cast<std::int64_t>(out.size())) / kSampleRate;
  for (std::size_t s = 0; s < sources.size(); ++s) {
    const SoundSource& source = sources[s];
    const double distance = (source.position - listener).norm();
    const double delay = distance / kSpeedOfSound;
    // Heard from start + delay to end + delay: most sources are silent for most blocks.
    if (block_end <= source.start() + delay || block_start >= source.end() + delay) continue;
    double gain = kReferenceDistance / std::max(distance, kMinDistance);
    for (int wall = 0; wall < (walls.empty() ? 0 : walls[s]); ++wall) gain *= kWallAttenuation;
    const double offset = delay + source.start();
    for (std::size_t k = 0; k < out.size(); ++k) {
      const double time = static_cast<double>(first_sample + static_cast<std::int64_t>(k)) / kSampleRate;
      out[k] += static_cast<float>(gain * source.pressure(time - offset));
    }
  }
}

std::int64_t sample_index(double time) {
  // The tolerance absorbs the rounding of times built from tick counts (60 × 1/60 is not exactly 1).
  return static_cast<std::int64_t>(std::ceil(time * kSampleRate - 1e-6));
}

double step_rate(double speed) {
  return speed < kMinStepSpeed ? 0.0 : kStepRate * std::sqrt(speed / kStepRateSpeed);
}

void footfalls(double& phase, double speed, double time, double dt, std::vector<double>& times) {
  const double rate = step_rate(speed);
  if (rate <= 0.0) return;
  // A foot lands whenever the phase passes a whole step.
  double next = (1.0 - phase) / rate;
  while (next < dt) {
    times.push_back(time + next);
    next += 1.0 / rate;
  }
  phase += rate * dt;
  phase -= std::floor(phase);
}

}  // namespace hrisim::sensors
