#pragma once
// Mono audio clips for sound sources: read from a RIFF WAVE file's bytes (PCM 16-bit or IEEE float
// 32-bit, mono or stereo mixed to mono) and resampled to the microphones' rate.
#include <cstdint>
#include <span>
#include <vector>

namespace hrisim::sensors {

/// Sample rates a clip may have, Hz: from telephone speech (8 kHz) to studio masters (192 kHz). Beyond
/// them resampling to the microphones' 16 kHz multiplies work and memory: a header saying 1 Hz made
/// 16,000 samples of each one (40 KB of file, 1.2 GB of clip).
inline constexpr std::uint32_t kMinClipSampleRate = 8000;
inline constexpr std::uint32_t kMaxClipSampleRate = 192000;
/// Longest clip, s: a minute, far beyond what a person says at once. Resampling costs 8 ms of CPU per
/// second of clip from 8 kHz and 98 ms from 192 kHz (measured: docs/limits.md), so a clip costs at most
/// about 6 s, and holds 3.8 MB at 16 kHz.
inline constexpr double kMaxClipSeconds = 60.0;

/// Mono samples at `sample_rate`, full scale ±1 (a source scales them to its level).
struct AudioClip {
  double sample_rate = 0.0;  ///< Hz
  std::vector<float> samples;

  double duration() const { return sample_rate > 0.0 ? static_cast<double>(samples.size()) / sample_rate : 0.0; }
};

/// The clip in a WAV file's bytes: format 1 (PCM, 16 bits) or 3 (IEEE float, 32 bits), also inside
/// WAVE_FORMAT_EXTENSIBLE; one or two channels, two averaged; kMinClipSampleRate to kMaxClipSampleRate,
/// at most kMaxClipSeconds. Throws core::Error(bad_request) with a message beginning "WAV: " when the
/// bytes are not RIFF/WAVE, the format, rate or length is another, or the file is cut short.
AudioClip read_wav(std::span<const std::uint8_t> bytes);

/// The clip at another sample rate, through a windowed-sinc low-pass at the lower rate's Nyquist
/// frequency (no aliasing when a 44.1 or 48 kHz clip goes down to 16 kHz). The same clip when the rates
/// agree. Throws as read_wav for a rate (either) or a length beyond the clip limits.
AudioClip resampled(const AudioClip& clip, double sample_rate);

}  // namespace hrisim::sensors
