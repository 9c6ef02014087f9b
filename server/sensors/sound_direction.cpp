#include "sensors/sound_direction.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "core/math.hpp"
#include "core/portable_math.hpp"

namespace hrisim::sensors {
namespace {

bool power_of_two(int n) { return n >= 2 && (n & (n - 1)) == 0; }

/// The window, checked before the FFTs are made: they need powers of two.
int checked_window(const DoaParams& params) {
  if (!power_of_two(params.window) || !power_of_two(params.upsampling)) {
    throw core::Error(core::ErrorCode::bad_request, "direction of arrival: the window (" + std::to_string(params.window) +
                                                        ") and the upsampling (" + std::to_string(params.upsampling) +
                                                        ") must be powers of two");
  }
  return params.window;
}

/// Complex product written out: std::complex's operator* calls a library routine for its NaN cases.
std::complex<double> times(const std::complex<double>& a, const std::complex<double>& b) {
  return {a.real() * b.real() - a.imag() * b.imag(), a.real() * b.imag() + a.imag() * b.real()};
}

}  // namespace

Fft::Fft(int size) {
  if (!power_of_two(size)) throw core::Error(core::ErrorCode::internal, "an FFT of " + std::to_string(size) + " points: not a power of two");
  twiddles_.resize(static_cast<std::size_t>(size / 2));
  for (std::size_t k = 0; k < twiddles_.size(); ++k) {
    const double turns = static_cast<double>(k) / size;
    twiddles_[k] = {core::cos_turns(turns), -core::sin_turns(turns)};
  }
}

void Fft::transform(std::span<std::complex<double>> data, bool inverse) const {
  const std::size_t n = data.size();
  // Bit-reversed order, then butterflies of doubling length (Cooley–Tukey, in place).
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(data[i], data[j]);
  }
  for (std::size_t length = 2; length <= n; length <<= 1) {
    const std::size_t half = length / 2, stride = n / length;
    for (std::size_t i = 0; i < n; i += length) {
      for (std::size_t k = 0; k < half; ++k) {
        const std::complex<double> twiddle = inverse ? std::conj(twiddles_[k * stride]) : twiddles_[k * stride];
        const std::complex<double> u = data[i + k], v = times(data[i + k + half], twiddle);
        data[i + k] = u + v;
        data[i + k + half] = u - v;
      }
    }
  }
}

DirectionOfArrival::DirectionOfArrival(std::span<const Vec3> microphones, DoaParams params)
    : params_(params),
      channels_(static_cast<int>(microphones.size())),
      reach_(0),
      azimuths_(std::max(1, static_cast<int>(std::lround(2.0 * std::numbers::pi / params.azimuth_step)))),
      fft_(checked_window(params)),
      upsampled_fft_(params.window * params.upsampling) {
  if (channels_ < 2) throw core::Error(core::ErrorCode::bad_request, "direction of arrival: an array needs two microphones at least");
  const double samples_per_metre = kSampleRate / kSpeedOfSound * params.upsampling;
  double widest = 0.0;
  for (int i = 0; i < channels_; ++i) {
    for (int j = i + 1; j < channels_; ++j) {
      const Vec3& a = microphones[static_cast<std::size_t>(i)];
      const Vec3& b = microphones[static_cast<std::size_t>(j)];
      Pair pair{i, j, std::vector<double>(static_cast<std::size_t>(azimuths_))};
      for (int k = 0; k < azimuths_; ++k) {
        // Towards the source; the microphone nearer it hears first, and the correlation of (i, j)
        // peaks at t_i − t_j = (u·b − u·a) / c.
        const double turns = static_cast<double>(k) / azimuths_;
        const double ux = core::cos_turns(turns), uy = core::sin_turns(turns);
        pair.lags[static_cast<std::size_t>(k)] = (ux * (b.x() - a.x()) + uy * (b.y() - a.y())) * samples_per_metre;
      }
      widest = std::max(widest, (b - a).head<2>().norm());
      pairs_.push_back(std::move(pair));
    }
  }
  reach_ = static_cast<int>(std::ceil(widest * samples_per_metre)) + 2;
  window_.resize(static_cast<std::size_t>(params.window));
  for (int n = 0; n < params.window; ++n) {
    const double s = core::sin_turns(0.5 * n / params.window);
    window_[static_cast<std::size_t>(n)] = s * s;
  }
  spectra_.assign(static_cast<std::size_t>(channels_), std::vector<std::complex<double>>(static_cast<std::size_t>(params.window)));
  cross_.resize(static_cast<std::size_t>(params.window) * static_cast<std::size_t>(params.upsampling));
}

void DirectionOfArrival::correlate(const Pair& first, const Pair* second, std::span<double> first_correlation,
                                   std::span<double> second_correlation) const {
  const int n = params_.window;
  const auto m = static_cast<int>(cross_.size());
  const int first_bin = std::max(1, static_cast<int>(std::ceil(params_.min_frequency * n / kSampleRate)));
  std::fill(cross_.begin(), cross_.end(), std::complex<double>());
  // The phase transform: every frequency counts alike, whatever its power.
  const auto phase_transformed = [&](const Pair& pair, int k, int& used) {
    const std::complex<double> product = times(spectra_[static_cast<std::size_t>(pair.first)][static_cast<std::size_t>(k)],
                                               std::conj(spectra_[static_cast<std::size_t>(pair.second)][static_cast<std::size_t>(k)]));
    const double magnitude = std::sqrt(product.real() * product.real() + product.imag() * product.imag());
    if (magnitude <= 0.0) return std::complex<double>();
    ++used;
    return product / magnitude;
  };
  int used_first = 0, used_second = 0;
  const std::complex<double> i(0.0, 1.0);
  for (int k = first_bin; k < n / 2; ++k) {
    const std::complex<double> a = phase_transformed(first, k, used_first);
    const std::complex<double> b = second ? phase_transformed(*second, k, used_second) : std::complex<double>();
    // Each spectrum is Hermitian (its correlation is real): A + iB at k, conj(A) + i conj(B) at m − k.
    cross_[static_cast<std::size_t>(k)] = a + times(i, b);
    cross_[static_cast<std::size_t>(m - k)] = std::conj(a) + times(i, std::conj(b));
  }
  upsampled_fft_.transform(cross_, true);
  const double first_scale = used_first > 0 ? 0.5 / used_first : 0.0;  // 1 at a lag where every frequency agrees
  const double second_scale = used_second > 0 ? 0.5 / used_second : 0.0;
  for (int lag = -reach_; lag <= reach_; ++lag) {
    const std::complex<double>& value = cross_[static_cast<std::size_t>((lag + m) % m)];
    first_correlation[static_cast<std::size_t>(lag + reach_)] = value.real() * first_scale;
    if (second) second_correlation[static_cast<std::size_t>(lag + reach_)] = value.imag() * second_scale;
  }
}

void DirectionOfArrival::transform_channels(std::span<const float> planar) const {
  const auto n = static_cast<std::size_t>(params_.window);
  const auto sample = [&](int c, std::size_t k) { return static_cast<double>(planar[static_cast<std::size_t>(c) * n + k]) * window_[k]; };
  for (int c = 0; c < channels_; c += 2) {
    auto& first = spectra_[static_cast<std::size_t>(c)];
    if (c + 1 == channels_) {
      for (std::size_t k = 0; k < n; ++k) first[k] = {sample(c, k), 0.0};
      fft_.transform(first, false);
      continue;
    }
    // Two real signals as one complex one, x + iy: X(k) = (Z(k) + conj Z(n − k)) / 2 and
    // Y(k) = (Z(k) − conj Z(n − k)) / 2i.
    auto& second = spectra_[static_cast<std::size_t>(c + 1)];
    for (std::size_t k = 0; k < n; ++k) second[k] = {sample(c, k), sample(c + 1, k)};
    fft_.transform(second, false);
    for (std::size_t k = 0; k < n; ++k) {
      const std::complex<double> z = second[k], mirror = std::conj(second[(n - k) % n]);
      first[k] = 0.5 * (z + mirror);
    }
    for (std::size_t k = 0; k <= n / 2; ++k) {
      const std::complex<double> z = second[k], mirror = std::conj(second[(n - k) % n]);
      const std::complex<double> y = 0.5 * (z - mirror);
      second[k] = {y.imag(), -y.real()};  // divided by i
    }
  }
}

std::optional<DoaReading> DirectionOfArrival::estimate(std::span<const float> planar) const {
  const auto n = static_cast<std::size_t>(params_.window);
  if (planar.size() != n * static_cast<std::size_t>(channels_)) {
    throw core::Error(core::ErrorCode::internal, "direction of arrival: " + std::to_string(planar.size()) + " samples for " +
                                                     std::to_string(channels_) + " channels of " + std::to_string(n));
  }
  double energy = 0.0;
  for (const float sample : planar) energy += static_cast<double>(sample) * sample;
  if (std::sqrt(energy / static_cast<double>(planar.size())) < params_.silence) return std::nullopt;

  transform_channels(planar);
  const auto span = static_cast<std::size_t>(2 * reach_ + 1);
  correlations_.resize(pairs_.size() * span);
  const std::span<double> correlations(correlations_);
  for (std::size_t p = 0; p < pairs_.size(); p += 2) {
    const bool two = p + 1 < pairs_.size();
    correlate(pairs_[p], two ? &pairs_[p + 1] : nullptr, correlations.subspan(p * span, span), two ? correlations.subspan((p + 1) * span, span) : std::span<double>());
  }

  DoaReading best{0.0, -std::numeric_limits<double>::infinity()};
  for (int k = 0; k < azimuths_; ++k) {
    double sum = 0.0;
    for (std::size_t p = 0; p < pairs_.size(); ++p) {
      // Linear interpolation between the upsampled lags.
      const double at = pairs_[p].lags[static_cast<std::size_t>(k)] + reach_;
      const double below = std::floor(at);
      const double f = at - below;
      const double* row = correlations_.data() + p * span + static_cast<std::size_t>(below);
      sum += (1.0 - f) * row[0] + f * row[1];
    }
    const double power = sum / static_cast<double>(pairs_.size());
    if (power > best.power) best = {core::wrap_angle(2.0 * std::numbers::pi * k / azimuths_), power};
  }
  return best;
}

}  // namespace hrisim::sensors
