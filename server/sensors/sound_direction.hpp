#pragma once
// Direction of arrival of the loudest sound at a microphone array: GCC-PHAT on every pair of
// microphones, combined as SRP-PHAT over a grid of azimuths in the plane of the array's link (x, y),
// on the last few ticks of audio. One source's direction; no tracking, no elevation, no count of sources.
#include <complex>
#include <optional>
#include <span>
#include <vector>

#include "sensors/sound.hpp"

namespace hrisim::sensors {

/// Samples of each channel an estimate reads: 4096, 0.256 s at 16 kHz, about a syllable of speech
/// and a power of two for the FFT.
inline constexpr int kDoaWindow = 4096;
/// Hz: lower frequencies are left out — a 0.1 m array spans 6% of a wavelength at 200 Hz, too little
/// for their phase to tell directions, while motors, doors and footsteps put most energy there.
inline constexpr double kDoaMinFrequency = 200.0;
/// Pa RMS over the window, mean over channels: quieter, no reading. 40 dB SPL, 10 dB above the
/// microphones' self-noise (kSelfNoise), so that their noise alone never gives a direction.
inline constexpr double kDoaSilence = 0.002;

struct DoaParams {
  int window = kDoaWindow;                ///< samples per channel, a power of two
  double azimuth_step = 3.14159265358979323846 / 180.0;  ///< rad, of the search grid
  double min_frequency = kDoaMinFrequency;  ///< Hz
  double silence = kDoaSilence;           ///< Pa RMS
  /// Cross-correlations are read between samples at this resolution (the spectrum zero-padded before
  /// the inverse FFT: band-limited interpolation), since a 0.1 m array spans under 5 samples.
  int upsampling = 4;
  double rate = 10.0;  ///< Hz, for the sensing schedule
};

struct DoaReading {
  /// rad, in the array's link frame: 0 along x, counter-clockwise about z, in (−π, π].
  double azimuth = 0.0;
  /// SRP-PHAT at the peak: the mean over microphone pairs of their phase-transformed cross-correlation
  /// at the lag of that direction, at most 1 (one source, no noise, no echo); near 0 for diffuse noise.
  double power = 0.0;
};

/// A radix-2 complex FFT of one size (a power of two), with its twiddle factors computed once.
class Fft {
 public:
  explicit Fft(int size);
  int size() const { return static_cast<int>(twiddles_.size() * 2); }
  /// In place; `inverse` without the 1/n scaling.
  void transform(std::span<std::complex<double>> data, bool inverse) const;

 private:
  std::vector<std::complex<double>> twiddles_;  ///< e^(−2πik/n), k < n/2
};

class DirectionOfArrival {
 public:
  /// `microphones` in the array's link frame (MicrophoneArray::positions). Throws
  /// core::Error(bad_request) for fewer than two microphones or a window that is no power of two.
  DirectionOfArrival(std::span<const Vec3> microphones, DoaParams params = {});
  const DoaParams& params() const { return params_; }

  /// The direction of the loudest sound in `planar` (channels × window samples, planar:
  /// AudioHistory::samples()), or nothing when the window is quieter than params().silence.
  std::optional<DoaReading> estimate(std::span<const float> planar) const;

 private:
  struct Pair {
    int first, second;
    std::vector<double> lags;  ///< per azimuth: where the pair's correlation peaks, upsampled samples
  };
  /// Two pairs' phase-transformed cross-correlations (the second may be null), upsampled, at lags
  /// [−reach_, reach_]: both are real, so one inverse FFT gives the first as its real part and the
  /// second as its imaginary part.
  void correlate(const Pair& first, const Pair* second, std::span<double> first_correlation, std::span<double> second_correlation) const;
  /// The spectra of every channel, two real channels per complex FFT.
  void transform_channels(std::span<const float> planar) const;

  DoaParams params_;
  int channels_, reach_, azimuths_;
  std::vector<Pair> pairs_;
  Fft fft_, upsampled_fft_;
  std::vector<double> window_;  ///< Hann
  mutable std::vector<std::vector<std::complex<double>>> spectra_;  ///< scratch of estimate: per channel
  mutable std::vector<std::complex<double>> cross_;                 ///< scratch: two pairs' upsampled spectra
  mutable std::vector<double> correlations_;                        ///< scratch: every pair's correlation near lag 0
};

}  // namespace hrisim::sensors
