#pragma once
// Mono audio clips for sound sources: read from a RIFF WAVE file's bytes (PCM 16-bit or IEEE float
// 32-bit, mono or stereo mixed to mono) and resampled to the microphones' rate.
#include <cstdint>
#include <span>
#include <vector>

namespace hrisim::sensors {

/// Mono samples at `sample_rate`, full scale ±1 (a source scales them to its level).
struct AudioClip {
  double sample_rate = 0.0;  ///< Hz
  std::vector<float> samples;

  double duration() const { return sample_rate > 0.0 ? static_cast<double>(samples.size()) / sample_rate : 0.0; }
};

/// The clip in a WAV file's bytes: format 1 (PCM, 16 bits) or 3 (IEEE float, 32 bits), also inside
/// WAVE_FORMAT_EXTENSIBLE; one or two channels, two averaged. Throws core::Error(bad_request) with a
/// message beginning "WAV: " when the bytes are not RIFF/WAVE, the format is another, or the file is cut short.
AudioClip read_wav(std::span<const std::uint8_t> bytes);

/// The clip at another sample rate, through a windowed-sinc low-pass at the lower rate's Nyquist
/// frequency (no aliasing when a 44.1 or 48 kHz clip goes down to 16 kHz). The same clip when the rates agree.
AudioClip resampled(const AudioClip& clip, double sample_rate);

}  // namespace hrisim::sensors
