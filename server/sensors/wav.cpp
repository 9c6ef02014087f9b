#include "sensors/wav.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>

#include "core/error.hpp"
#include "core/portable_math.hpp"

namespace hrisim::sensors {
namespace {

constexpr std::uint16_t kFormatPcm = 1;
constexpr std::uint16_t kFormatFloat = 3;
constexpr std::uint16_t kFormatExtensible = 0xFFFE;

/// Zero crossings of the resampling kernel on each side: its stop band is about 60 dB down, more than
/// 16-bit clips played at speech levels need.
constexpr double kResamplerZeroCrossings = 16.0;
/// The resampler's cut-off as a share of the lower Nyquist frequency: room for the kernel's transition band.
constexpr double kResamplerCutoff = 0.95;

[[noreturn]] void fail(const std::string& message) { throw core::Error(core::ErrorCode::bad_request, "WAV: " + message); }

/// Little-endian reads; the caller has checked the bounds.
std::uint16_t u16(std::span<const std::uint8_t> bytes, std::size_t at) {
  return static_cast<std::uint16_t>(bytes[at] | (bytes[at + 1] << 8));
}
std::uint32_t u32(std::span<const std::uint8_t> bytes, std::size_t at) {
  return static_cast<std::uint32_t>(u16(bytes, at)) | (static_cast<std::uint32_t>(u16(bytes, at + 2)) << 16);
}
bool tag_is(std::span<const std::uint8_t> bytes, std::size_t at, std::string_view tag) {
  return std::equal(tag.begin(), tag.end(), bytes.begin() + static_cast<std::ptrdiff_t>(at),
                    [](char a, std::uint8_t b) { return static_cast<std::uint8_t>(a) == b; });
}

struct Format {
  std::uint16_t tag = 0;
  int channels = 0;
  std::uint32_t sample_rate = 0;
  int block_align = 0;
  int bits = 0;
};

void check_rate(double rate) {
  if (!(rate >= kMinClipSampleRate && rate <= kMaxClipSampleRate)) {
    fail("the sample rate is " + std::to_string(static_cast<std::uint64_t>(std::max(rate, 0.0))) + " Hz; clips are read at " +
         std::to_string(kMinClipSampleRate) + " to " + std::to_string(kMaxClipSampleRate) + " Hz");
  }
}

void check_length(std::size_t samples, double rate) {
  const double seconds = static_cast<double>(samples) / rate;
  if (seconds > kMaxClipSeconds) {
    fail("the clip lasts " + std::to_string(static_cast<long long>(std::ceil(seconds))) + " s, more than the " +
         std::to_string(static_cast<int>(kMaxClipSeconds)) + " s a clip may last");
  }
}

Format read_format(std::span<const std::uint8_t> chunk) {
  if (chunk.size() < 16) fail("the fmt chunk has " + std::to_string(chunk.size()) + " bytes, fewer than 16");
  Format format{u16(chunk, 0), u16(chunk, 2), u32(chunk, 4), u16(chunk, 12), u16(chunk, 14)};
  if (format.tag == kFormatExtensible) {
    if (chunk.size() < 26) fail("the extensible fmt chunk is cut short");
    format.tag = u16(chunk, 24);  // the sub-format GUID begins with the plain format tag
  }
  const bool pcm16 = format.tag == kFormatPcm && format.bits == 16;
  const bool float32 = format.tag == kFormatFloat && format.bits == 32;
  if (!pcm16 && !float32) {
    fail("unsupported format " + std::to_string(format.tag) + " with " + std::to_string(format.bits) +
         " bits; only 16-bit PCM (1) and 32-bit float (3) are read");
  }
  if (format.channels != 1 && format.channels != 2) fail(std::to_string(format.channels) + " channels; only mono and stereo are read");
  check_rate(format.sample_rate);
  if (format.block_align != format.channels * format.bits / 8) fail("the block align does not match the channels and bits");
  return format;
}

float sample_at(std::span<const std::uint8_t> data, std::size_t at, const Format& format) {
  if (format.tag == kFormatPcm) return static_cast<float>(static_cast<std::int16_t>(u16(data, at))) / 32768.0f;
  const float value = std::bit_cast<float>(u32(data, at));
  if (!std::isfinite(value)) fail("a sample at byte " + std::to_string(at) + " of the data is not a finite number");
  return value;
}

AudioClip decode(std::span<const std::uint8_t> data, const Format& format) {
  const auto frame = static_cast<std::size_t>(format.block_align);
  if (data.size() % frame != 0) fail("the data chunk ends inside a frame (truncated)");
  check_length(data.size() / frame, format.sample_rate);
  AudioClip clip{static_cast<double>(format.sample_rate), std::vector<float>(data.size() / frame)};
  const std::size_t width = static_cast<std::size_t>(format.bits / 8);
  for (std::size_t i = 0; i < clip.samples.size(); ++i) {
    float sum = 0.0f;
    for (int c = 0; c < format.channels; ++c) sum += sample_at(data, i * frame + static_cast<std::size_t>(c) * width, format);
    clip.samples[i] = sum / static_cast<float>(format.channels);
  }
  return clip;
}

/// Hann-windowed sinc of the low-pass with cut-off `band` (a share of the input rate, ≤ 1/2), at `u` input samples.
double kernel(double u, double band, double half_width) {
  if (std::abs(u) >= half_width) return 0.0;
  const double window = 0.5 + 0.5 * core::cos_turns(0.5 * u / half_width);
  const double z = 2.0 * band * u;
  const double sinc = z == 0.0 ? 1.0 : core::sin_turns(0.5 * z) / (std::numbers::pi * z);
  return 2.0 * band * sinc * window;
}

}  // namespace

AudioClip read_wav(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < 12 || !tag_is(bytes, 0, "RIFF") || !tag_is(bytes, 8, "WAVE")) fail("not a RIFF/WAVE file");
  std::optional<Format> format;
  std::size_t at = 12;
  while (at + 8 <= bytes.size()) {
    const std::size_t size = u32(bytes, at + 4);
    const std::size_t body = at + 8;
    if (size > bytes.size() - body) {
      fail("the '" + std::string(bytes.begin() + static_cast<std::ptrdiff_t>(at), bytes.begin() + static_cast<std::ptrdiff_t>(at) + 4) +
           "' chunk declares " + std::to_string(size) + " bytes but " + std::to_string(bytes.size() - body) + " follow (truncated)");
    }
    const auto chunk = bytes.subspan(body, size);
    if (tag_is(bytes, at, "fmt ")) format = read_format(chunk);
    if (tag_is(bytes, at, "data")) {
      if (!format) fail("the data chunk comes before any fmt chunk");
      return decode(chunk, *format);
    }
    at = body + size + (size % 2);  // chunks are padded to an even length
  }
  fail(format ? "no data chunk (truncated)" : "no fmt chunk (truncated)");
}

AudioClip resampled(const AudioClip& clip, double sample_rate) {
  if (clip.sample_rate == sample_rate) return clip;
  check_rate(clip.sample_rate);
  check_rate(sample_rate);
  check_length(clip.samples.size(), clip.sample_rate);
  if (clip.samples.empty()) return AudioClip{sample_rate, {}};
  const double ratio = clip.sample_rate / sample_rate;                               // input samples per output sample
  const double band = 0.5 * kResamplerCutoff * std::min(1.0, 1.0 / ratio);         // cut-off, share of the input rate
  const double half_width = kResamplerZeroCrossings / (2.0 * band);                 // input samples
  AudioClip out{sample_rate, std::vector<float>(static_cast<std::size_t>(std::floor(clip.duration() * sample_rate)))};
  const auto last = static_cast<std::ptrdiff_t>(clip.samples.size()) - 1;
  for (std::size_t n = 0; n < out.samples.size(); ++n) {
    const double centre = static_cast<double>(n) * ratio;
    const auto first = std::max<std::ptrdiff_t>(0, static_cast<std::ptrdiff_t>(std::ceil(centre - half_width)));
    const auto end = std::min<std::ptrdiff_t>(last, static_cast<std::ptrdiff_t>(std::floor(centre + half_width)));
    double sum = 0.0;
    for (std::ptrdiff_t k = first; k <= end; ++k) sum += clip.samples[static_cast<std::size_t>(k)] * kernel(centre - static_cast<double>(k), band, half_width);
    out.samples[n] = static_cast<float>(sum);
  }
  return out;
}

}  // namespace hrisim::sensors
