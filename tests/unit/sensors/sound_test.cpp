#include <gtest/gtest.h>

#include <cmath>
#include <chrono>
#include <complex>
#include <cstring>
#include <numbers>
#include <vector>

#include "core/error.hpp"
#include "core/portable_math.hpp"
#include "robots/description.hpp"
#include "sensors/microphones.hpp"
#include "sensors/sound.hpp"
#include "sensors/sound_direction.hpp"
#include "sensors/wav.hpp"

namespace hrisim::sensors {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTick = 1.0 / 60.0;

/// The samples [first, first + count) at `listener` of the sources, open space.
std::vector<float> listen(std::span<const SoundSource> sources, const Vec3& listener, std::int64_t first, int count,
                          std::span<const int> walls = {}) {
  std::vector<float> samples(static_cast<std::size_t>(count), 0.0f);
  propagate(sources, walls, listener, first, samples);
  return samples;
}

double rms(std::span<const float> samples) {
  double sum = 0.0;
  for (const float sample : samples) sum += static_cast<double>(sample) * sample;
  return std::sqrt(sum / static_cast<double>(samples.size()));
}

SoundSource speaker_at(const Vec3& position, double start = 0.0, double duration = 2.0, std::uint64_t voice = 7) {
  SoundSource speech = SoundSource::speech(voice, 1, start, duration);
  speech.position = position;
  return speech;
}

TEST(Sound, PressureFallsInverselyWithDistance) {
  const std::vector<SoundSource> sources{speaker_at({0.0, 0.0, 1.5})};
  // Both listeners hear the whole utterance within the four seconds.
  const auto near = listen(sources, {1.0, 0.0, 1.5}, 0, 64000);
  const auto far = listen(sources, {2.0, 0.0, 1.5}, 0, 64000);
  EXPECT_NEAR(rms(far) / rms(near), 0.5, 0.005);
  // At 1 m the level is the named one (over the utterance's 2 s; expected over syllables, so not exact).
  EXPECT_NEAR(rms(near) * std::sqrt(64000.0 / 32000.0), kSpeechLevel, 0.25 * kSpeechLevel);
  // Inside kMinDistance the gain stops growing.
  const auto touching = listen(sources, {0.01, 0.0, 1.5}, 0, 64000);
  EXPECT_NEAR(rms(touching) / rms(near), 1.0 / kMinDistance, 0.1);
}

TEST(Sound, EachKindHasItsLevelAtOneMetre) {
  const auto clip = std::make_shared<AudioClip>(AudioClip{8000.0, std::vector<float>(8000)});
  for (std::size_t i = 0; i < clip->samples.size(); ++i) clip->samples[i] = static_cast<float>(0.3 * std::sin(0.7 * static_cast<double>(i)));
  const std::vector<std::pair<SoundSource, double>> cases{
      {SoundSource::footstep(3, 0.0), kFootstepLevel}, {SoundSource::door(3, 0.0), kDoorLevel},
      {SoundSource::bell(0.0, 2), kBellLevel},        {SoundSource::clip(clip, 0.0, 0.05), 0.05},
      {SoundSource::motor(3, 0.01), 0.01}};
  for (const auto& [source, level] : cases) {
    const double length = std::isinf(source.end()) ? 1.0 : source.end() - source.start();
    const int count = static_cast<int>(std::lround(length * kSampleRate));
    double sum = 0.0;
    for (int k = 0; k < count; ++k) sum += std::pow(source.pressure(k / kSampleRate), 2);
    EXPECT_NEAR(std::sqrt(sum / count), level, 0.03 * level) << "kind " << static_cast<int>(source.kind());
  }
}

TEST(Sound, ArrivesAfterTheDistanceAtTheSpeedOfSound) {
  const std::vector<SoundSource> sources{speaker_at({0.0, 0.0, 1.5}, 0.0, 1.0)};
  const auto near = listen(sources, {1.0, 0.0, 1.5}, 0, 16000);
  const auto far = listen(sources, {3.0, 0.0, 1.5}, 0, 16000);
  // The lag where far[n] best matches near[n - lag], refined by a parabola through the peak.
  std::vector<double> correlation(200, 0.0);
  for (int lag = 0; lag < 200; ++lag) {
    for (int n = lag; n < 16000; ++n) correlation[static_cast<std::size_t>(lag)] += static_cast<double>(far[static_cast<std::size_t>(n)]) * near[static_cast<std::size_t>(n - lag)];
  }
  const auto peak = static_cast<int>(std::max_element(correlation.begin() + 1, correlation.end() - 1) - correlation.begin());
  const double left = correlation[static_cast<std::size_t>(peak - 1)], centre = correlation[static_cast<std::size_t>(peak)],
               right = correlation[static_cast<std::size_t>(peak + 1)];
  const double lag = peak + 0.5 * (left - right) / (left - 2.0 * centre + right);
  EXPECT_NEAR(lag, (3.0 - 1.0) / kSpeedOfSound * kSampleRate, 0.25);
  // Nothing arrives before the delay: the first 1 m / 343 m/s = 46.6 samples at the near listener are silent.
  for (int n = 0; n <= 46; ++n) EXPECT_EQ(near[static_cast<std::size_t>(n)], 0.0f) << n;
  EXPECT_NE(near[48], 0.0f);
}

TEST(Sound, EachWallCrossedAttenuatesByTheNamedFactor) {
  const std::vector<SoundSource> sources{speaker_at({0.0, 0.0, 1.5})};
  const Vec3 listener(4.0, 0.0, 1.5);
  const auto open = listen(sources, listener, 8000, 4000);
  const std::vector<int> one{1}, two{2};
  const auto behind_one = listen(sources, listener, 8000, 4000, one);
  const auto behind_two = listen(sources, listener, 8000, 4000, two);
  ASSERT_GT(rms(open), 0.0);
  for (std::size_t k = 0; k < open.size(); ++k) {
    EXPECT_NEAR(behind_one[k], open[k] * kWallAttenuation, 1e-6 * std::abs(open[k]) + 1e-12);
    EXPECT_NEAR(behind_two[k], open[k] * kWallAttenuation * kWallAttenuation, 1e-6 * std::abs(open[k]) + 1e-12);
  }
  EXPECT_NEAR(20.0 * std::log10(kWallAttenuation), -33.0, 1e-9);
}

TEST(Sound, SourcesAreSilentBeforeTheirStartAndFromTheirEnd) {
  const auto clip = std::make_shared<AudioClip>(AudioClip{16000.0, std::vector<float>(1600, 0.5f)});
  const std::vector<SoundSource> sources{SoundSource::speech(1, 2, 5.0, 1.5), SoundSource::footstep(1, 5.0),
                                         SoundSource::door(1, 5.0), SoundSource::bell(5.0), SoundSource::clip(clip, 5.0)};
  for (const SoundSource& source : sources) {
    const double length = source.end() - source.start();
    EXPECT_EQ(source.pressure(-1e-9), 0.0);
    EXPECT_EQ(source.pressure(-1.0), 0.0);
    EXPECT_EQ(source.pressure(length + 1e-9), 0.0);
    EXPECT_EQ(source.pressure(length + 0.5), 0.0);
    double inside = 0.0;
    for (int k = 0; k < 200; ++k) inside = std::max(inside, std::abs(source.pressure(0.5 * length + k / kSampleRate)));
    EXPECT_GT(inside, 0.0) << static_cast<int>(source.kind());
    // A block before the sound arrives and one after it has passed are all zeros.
    for (const auto& block : {listen(std::span(&source, 1), {2.0, 0.0, 0.0}, 0, 16000 * 5),
                              listen(std::span(&source, 1), {2.0, 0.0, 0.0}, sample_index(source.end() + 0.01), 16000)}) {
      EXPECT_EQ(rms(block), 0.0) << static_cast<int>(source.kind());
    }
  }
  EXPECT_TRUE(std::isinf(SoundSource::motor(1, 0.01).end()));
}

/// A built-in robot's microphone array, from its description's mounts.
MicrophoneArray array_of(const char* robot) { return *microphone_array(*robots::builtin_robot(robot)); }

AudioBlock record_once(std::uint64_t seed) {
  std::vector<SoundSource> sources{speaker_at({2.0, 1.0, 1.6}), SoundSource::door(4, 0.1), SoundSource::bell(0.2)};
  sources[1].position = {-1.0, 3.0, 1.0};
  const Microphones microphones(array_of("hsr"));
  core::Random random(seed);
  AudioBlock block;
  const WallCount walls = [](const Vec3& source, const Vec3&) { return source.y() > 2.0 ? 1 : 0; };
  microphones.record(sources, walls, Eigen::Isometry3d(Eigen::Translation3d(0.0, 0.0, 1.0)), sample_index(0.5), 267,
                     MotorNoise{{0.0, 0.0, 0.1}, 0.7}, random, block);
  return block;
}

TEST(Sound, SameInputsGiveTheSameBits) {
  const AudioBlock a = record_once(11), b = record_once(11), c = record_once(12);
  ASSERT_EQ(a.data.size(), 4u * 267u);
  EXPECT_EQ(std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)), 0);
  EXPECT_NE(std::memcmp(a.data.data(), c.data.data(), a.data.size() * sizeof(float)), 0) << "the self-noise follows the seed";
  // A source evaluated twice at the same age gives the same value.
  const SoundSource speech = SoundSource::speech(5, 6, 0.0, 1.0);
  EXPECT_EQ(speech.pressure(0.123456789), SoundSource::speech(5, 6, 0.0, 1.0).pressure(0.123456789));
}

TEST(Sound, TicksJoinWithoutGapOrOverlap) {
  std::int64_t total = 0;
  for (int tick = 0; tick < 60; ++tick) total += sample_index((tick + 1) * kTick) - sample_index(tick * kTick);
  EXPECT_EQ(total, 16000);
  EXPECT_EQ(sample_index(0.0), 0);
  EXPECT_EQ(sample_index(60 * kTick), 16000);
}

TEST(Sound, FootfallsFollowTheWalkingSpeed) {
  EXPECT_NEAR(step_rate(kStepRateSpeed), kStepRate, 1e-12);
  EXPECT_EQ(step_rate(0.05), 0.0);
  double phase = 0.0;
  std::vector<double> times;
  for (int tick = 0; tick < 600; ++tick) {
    const std::size_t before = times.size();
    footfalls(phase, 1.3, tick * kTick, kTick, times);
    for (std::size_t i = before; i < times.size(); ++i) {
      EXPECT_GE(times[i], tick * kTick);
      EXPECT_LT(times[i], (tick + 1) * kTick);
    }
  }
  EXPECT_NEAR(static_cast<double>(times.size()), 20.0, 1.0);  // 10 s at 2 steps a second
  for (std::size_t i = 1; i < times.size(); ++i) EXPECT_NEAR(times[i] - times[i - 1], 0.5, 1e-9);
  times.clear();
  for (int tick = 0; tick < 600; ++tick) footfalls(phase, 0.05, tick * kTick, kTick, times);
  EXPECT_TRUE(times.empty());
}

void put(std::vector<std::uint8_t>& bytes, std::uint32_t value, int size) {
  for (int i = 0; i < size; ++i) bytes.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}

std::vector<std::uint8_t> wav(std::uint16_t format, std::uint16_t channels, std::uint32_t rate, std::uint16_t bits,
                              const std::vector<std::uint8_t>& data) {
  std::vector<std::uint8_t> bytes{'R', 'I', 'F', 'F'};
  put(bytes, static_cast<std::uint32_t>(36 + data.size()), 4);
  for (const char c : std::string("WAVEfmt ")) bytes.push_back(static_cast<std::uint8_t>(c));
  put(bytes, 16, 4);
  put(bytes, format, 2);
  put(bytes, channels, 2);
  put(bytes, rate, 4);
  put(bytes, rate * channels * bits / 8, 4);
  put(bytes, static_cast<std::uint32_t>(channels * bits / 8), 2);
  put(bytes, bits, 2);
  for (const char c : std::string("data")) bytes.push_back(static_cast<std::uint8_t>(c));
  put(bytes, static_cast<std::uint32_t>(data.size()), 4);
  bytes.insert(bytes.end(), data.begin(), data.end());
  return bytes;
}

TEST(Wav, ReadsPcm16AndStereoFloat) {
  const std::vector<std::int16_t> values{0, 16384, -32768, 32767, -1};
  std::vector<std::uint8_t> data;
  for (const std::int16_t value : values) put(data, static_cast<std::uint16_t>(value), 2);
  const AudioClip clip = read_wav(wav(1, 1, 22050, 16, data));
  EXPECT_EQ(clip.sample_rate, 22050.0);
  ASSERT_EQ(clip.samples.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i) EXPECT_EQ(clip.samples[i], values[i] / 32768.0f);

  std::vector<std::uint8_t> stereo;
  for (const float value : {0.5f, -0.25f, 1.0f, 1.0f}) put(stereo, std::bit_cast<std::uint32_t>(value), 4);
  const AudioClip mixed = read_wav(wav(3, 2, 16000, 32, stereo));
  ASSERT_EQ(mixed.samples.size(), 2u);
  EXPECT_EQ(mixed.samples[0], 0.125f);
  EXPECT_EQ(mixed.samples[1], 1.0f);
}

void expect_wav_error(const std::vector<std::uint8_t>& bytes, const std::string& words) {
  try {
    read_wav(bytes);
    ADD_FAILURE() << "no error; expected one about " << words;
  } catch (const core::Error& error) {
    EXPECT_EQ(error.code(), core::ErrorCode::bad_request);
    EXPECT_NE(std::string(error.what()).find("WAV: "), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
  }
}

TEST(Wav, ExplainsWhatItCannotRead) {
  const std::vector<std::uint8_t> data(8, 0);
  expect_wav_error({'O', 'g', 'g', 'S', 0, 0, 0, 0, 'W', 'A', 'V', 'E'}, "not a RIFF/WAVE file");
  expect_wav_error({'R', 'I', 'F'}, "not a RIFF/WAVE file");
  expect_wav_error(wav(1, 1, 16000, 8, data), "unsupported format 1 with 8 bits");
  expect_wav_error(wav(2, 1, 16000, 16, data), "unsupported format 2");
  expect_wav_error(wav(1, 6, 16000, 16, std::vector<std::uint8_t>(12, 0)), "6 channels");
  std::vector<std::uint8_t> cut = wav(1, 1, 16000, 16, data);
  cut.resize(cut.size() - 3);
  expect_wav_error(cut, "truncated");
  std::vector<std::uint8_t> header_only = wav(1, 1, 16000, 16, {});
  header_only.resize(header_only.size() - 8);  // no data chunk
  expect_wav_error(header_only, "no data chunk");
  expect_wav_error(wav(1, 1, 16000, 16, std::vector<std::uint8_t>(5, 0)), "inside a frame");
}

// Issue 40, finding 8: a clip whose header said 1 Hz was resampled to 16 kHz, 16,000 samples of each
// one: 40 KB of file took 198 s and kept 1.2 GB.
TEST(Wav, AClipWhoseHeaderSays1HzIsRefusedNotResampled) {
  const std::vector<std::uint8_t> data(40000, 0);
  const auto started = std::chrono::steady_clock::now();
  expect_wav_error(wav(1, 1, 1, 16, data), "the sample rate is 1 Hz; clips are read at 8000 to 192000 Hz");
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(5)) << "refused before any work";
  const AudioClip decoded{1.0, std::vector<float>(20000)};
  EXPECT_THROW(resampled(decoded, kSampleRate), core::Error) << "resampling checks the rate too";
  // Found by fuzz_wav: an empty clip kept its own rate when resampled.
  EXPECT_EQ(resampled(AudioClip{44100.0, {}}, kSampleRate).sample_rate, kSampleRate);
}

TEST(Wav, RatesFrom8To192KilohertzAreRead) {
  const std::vector<std::uint8_t> data(4, 0);
  EXPECT_EQ(read_wav(wav(1, 1, kMinClipSampleRate, 16, data)).sample_rate, 8000.0);
  EXPECT_EQ(read_wav(wav(1, 1, kMaxClipSampleRate, 16, data)).sample_rate, 192000.0);
  expect_wav_error(wav(1, 1, 7999, 16, data), "the sample rate is 7999 Hz");
  expect_wav_error(wav(1, 1, 192001, 16, data), "the sample rate is 192001 Hz");
  expect_wav_error(wav(1, 1, 0, 16, data), "the sample rate is 0 Hz");
  expect_wav_error(wav(1, 1, 0xFFFFFFFFu, 16, data), "the sample rate is 4294967295 Hz");
}

TEST(Wav, AClipLongerThanTheLimitIsRefused) {
  const auto frames = static_cast<std::size_t>(kMaxClipSeconds * kMinClipSampleRate);
  EXPECT_EQ(read_wav(wav(1, 1, kMinClipSampleRate, 16, std::vector<std::uint8_t>(2 * frames, 0))).samples.size(), frames);
  expect_wav_error(wav(1, 1, kMinClipSampleRate, 16, std::vector<std::uint8_t>(2 * frames + 2, 0)),
                   "the clip lasts 61 s, more than the 60 s a clip may last");
  const AudioClip decoded{8000.0, std::vector<float>(frames + 1)};
  EXPECT_THROW(resampled(decoded, kSampleRate), core::Error);
}

TEST(Wav, ResamplesWithoutAliasing) {
  AudioClip clip{48000.0, std::vector<float>(48000)};
  const auto tone = [&clip](double frequency) {
    for (std::size_t i = 0; i < clip.samples.size(); ++i) clip.samples[i] = static_cast<float>(std::sin(2.0 * kPi * frequency * static_cast<double>(i) / 48000.0));
    return resampled(clip, kSampleRate);
  };
  const AudioClip kept = tone(1000.0);
  ASSERT_EQ(kept.samples.size(), 16000u);
  // Away from the clip's ends, the 1 kHz tone is as it was.
  for (std::size_t n = 200; n < 15800; n += 37) EXPECT_NEAR(kept.samples[n], std::sin(2.0 * kPi * 1000.0 * static_cast<double>(n) / 16000.0), 0.01);
  // 12 kHz is above the new Nyquist frequency: gone, not folded down to 4 kHz.
  const AudioClip removed = tone(12000.0);
  EXPECT_LT(rms(std::span(removed.samples).subspan(200, 15600)), 0.01);
}

TEST(Fft, MatchesTheDiscreteFourierTransform) {
  const Fft fft(16);
  std::vector<std::complex<double>> data(16), original(16);
  for (int n = 0; n < 16; ++n) original[static_cast<std::size_t>(n)] = {std::sin(1.3 * n) + 0.1 * n, std::cos(0.4 * n * n)};
  data = original;
  fft.transform(data, false);
  for (int k = 0; k < 16; ++k) {
    std::complex<double> sum;
    for (int n = 0; n < 16; ++n) sum += original[static_cast<std::size_t>(n)] * std::polar(1.0, -2.0 * kPi * k * n / 16.0);
    EXPECT_NEAR(std::abs(data[static_cast<std::size_t>(k)] - sum), 0.0, 1e-9) << k;
  }
  fft.transform(data, true);
  for (int n = 0; n < 16; ++n) EXPECT_NEAR(std::abs(data[static_cast<std::size_t>(n)] / 16.0 - original[static_cast<std::size_t>(n)]), 0.0, 1e-9);
  EXPECT_NEAR(core::sin_turns(0.125), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(core::cos_turns(1234.25), 0.0, 1e-9);
}

struct Robot {
  MicrophoneArray array;
  Eigen::Isometry3d link_pose;  ///< the array's link in the map frame
  MotorNoise motors;
};

/// Where the array's link is: at (1, 2) heading 0.3 rad, at `height`; the motors `below` it.
Robot mount(MicrophoneArray array, double height, double below) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translate(Eigen::Vector3d(1.0, 2.0, height));
  pose.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  return {std::move(array), pose, {{1.0, 2.0, height - below}, 0.5}};
}

/// The direction the array hears a person speaking 3 m away at `azimuth` (in the array's frame),
/// after `ticks` ticks at 60 Hz, the microphones' noise and the motors (half load) on.
std::optional<DoaReading> hear(const Robot& robot, double azimuth, int ticks, std::uint64_t voice) {
  const Vec3 centre = robot.link_pose * robot.array.centre();
  const double heading = 0.3 + azimuth;
  std::vector<SoundSource> sources{speaker_at({centre.x() + 3.0 * std::cos(heading), centre.y() + 3.0 * std::sin(heading), 1.6}, 0.0, 3.0, voice)};
  const Microphones microphones(robot.array);
  const DirectionOfArrival doa(robot.array.positions);
  AudioHistory history(microphones.channels(), doa.params().window);
  core::Random random(voice);
  AudioBlock block;
  for (int tick = 0; tick < ticks; ++tick) {
    const std::int64_t first = sample_index(tick * kTick);
    microphones.record(sources, {}, robot.link_pose, first, static_cast<int>(sample_index((tick + 1) * kTick) - first),
                       robot.motors, random, block);
    history.add(block);
  }
  return doa.estimate(history.samples());
}

double angle_error(double a, double b) { return std::abs(std::remainder(a - b, 2.0 * kPi)); }

TEST(DirectionOfArrival, LocatesASpeakerWithinTenDegrees) {
  // The test: open space, 3 m, the microphones' self-noise and the robot's motors on.
  const std::vector<std::pair<const char*, Robot>> robots{{"hsr", mount(array_of("hsr"), 0.95, 0.85)},
                                                          {"roman", mount(array_of("roman"), 1.32, 0.5)}};
  for (const auto& [name, mounted] : robots) {
    std::uint64_t voice = 0;
    for (const double degrees : {0.0, 45.0, 100.0, -135.0, 170.0}) {
      const double azimuth = degrees * kPi / 180.0;
      for (const int ticks : {30, 75, 140}) {
        const auto reading = hear(mounted, azimuth, ticks, ++voice);
        ASSERT_TRUE(reading.has_value()) << name << " " << degrees << "°";
        EXPECT_LT(angle_error(reading->azimuth, azimuth) * 180.0 / kPi, 10.0)
            << name << ": at " << degrees << "° after " << ticks << " ticks heard " << reading->azimuth * 180.0 / kPi << "°";
        // Microphone noise alone peaks near 0.02, the motors alone (from below) near 0.1.
        EXPECT_GT(reading->power, 0.12) << name << " " << degrees << "°";
      }
    }
  }
}

TEST(DirectionOfArrival, SaysNothingInSilence) {
  const Robot hsr = mount(array_of("hsr"), 0.95, 0.85);
  const Microphones microphones(hsr.array);
  const DirectionOfArrival doa(hsr.array.positions);
  AudioHistory history(microphones.channels(), doa.params().window);
  EXPECT_FALSE(doa.estimate(history.samples()).has_value()) << "an empty history";
  core::Random random(3);
  AudioBlock block;
  for (int tick = 0; tick < 20; ++tick) {
    microphones.record({}, {}, hsr.link_pose, sample_index(tick * kTick), 267, MotorNoise{}, random, block);
    history.add(block);
  }
  EXPECT_NEAR(rms(history.channel(0)), kSelfNoise, 0.05 * kSelfNoise);
  EXPECT_FALSE(doa.estimate(history.samples()).has_value()) << "only the microphones' own noise";
  // Heard all the same, their noise has no direction: SRP-PHAT stays low.
  DoaParams deaf;
  deaf.silence = 0.0;
  const auto noise = DirectionOfArrival(hsr.array.positions, deaf).estimate(history.samples());
  ASSERT_TRUE(noise.has_value());
  EXPECT_LT(noise->power, 0.05);
}

TEST(Microphones, MotorNoiseHasItsLevelAtTheArray) {
  MicrophonesParams params;
  params.self_noise = 0.0;
  const Robot hsr = mount(array_of("hsr"), 0.95, 0.85);
  const Microphones microphones(hsr.array, params);
  core::Random random(5);
  AudioBlock block;
  microphones.record({}, {}, hsr.link_pose, 0, 16000, MotorNoise{hsr.motors.position, 0.8}, random, block);
  EXPECT_NEAR(rms(block.channel(2)), 0.8 * kMotorNoiseLevel, 0.05 * kMotorNoiseLevel);
}

}  // namespace
}  // namespace hrisim::sensors
