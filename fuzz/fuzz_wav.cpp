// Fuzz target: a WAV clip's bytes, read and resampled to the microphones' rate as a scenario's clip
// is, within the clip limits (sample rates, length); the resampled clip must stay within them.
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/error.hpp"
#include "sensors/sound.hpp"
#include "sensors/wav.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hrisim::sensors;
  try {
    const AudioClip clip = read_wav(std::span(data, size));
    const AudioClip heard = resampled(clip, kSampleRate);
    if (heard.sample_rate != kSampleRate || heard.duration() > kMaxClipSeconds) __builtin_trap();
  } catch (const hrisim::core::Error&) {
    // A file it cannot read is refused in words; that is fine.
  }
  return 0;
}
