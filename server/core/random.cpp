#include "core/random.hpp"

#include <random>

#include <array>
#include <bit>
#include <cmath>

namespace hrisim::core {
namespace {

/// The ziggurat (Marsaglia and Tsang, 2000): the normal density covered by 128 layers of equal area,
/// the base layer with the tail beyond kTailStart. Layer i ≥ 1 is [0, x[i]] wide; below x[i + 1] a point
/// of it is under the curve for sure, which settles 98.8 % of draws with one multiplication.
constexpr int kZigguratLayers = 128;
constexpr double kTailStart = 3.442619855899;        ///< R: where the tail begins
constexpr double kLayerArea = 9.91256303526217e-3;   ///< V: each layer's area under exp(-x²/2)

struct Ziggurat {
  std::array<double, kZigguratLayers + 1> x{};  ///< layer widths: x[0] = V / f(R) (the base), x[1] = R, x[128] = 0
  std::array<double, kZigguratLayers> inner{};  ///< x[i + 1] / x[i]: the share of layer i surely under the curve
};

const Ziggurat& ziggurat() {
  static const Ziggurat table = [] {
    Ziggurat z;
    double density = std::exp(-0.5 * kTailStart * kTailStart);
    z.x[0] = kLayerArea / density;
    z.x[1] = kTailStart;
    for (int i = 2; i < kZigguratLayers; ++i) {
      z.x[i] = std::sqrt(-2.0 * std::log(kLayerArea / z.x[i - 1] + density));
      density = std::exp(-0.5 * z.x[i] * z.x[i]);
    }
    z.x[kZigguratLayers] = 0.0;
    for (int i = 0; i < kZigguratLayers; ++i) z.inner[i] = z.x[i + 1] / z.x[i];
    return z;
  }();
  return table;
}

std::uint64_t splitmix64(std::uint64_t& x) {
  std::uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

std::uint64_t fnv1a(std::string_view bytes, std::uint64_t hash) {
  for (unsigned char c : bytes) {
    hash ^= c;
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

Random::Random(std::uint64_t seed) : seed_(seed) {
  std::uint64_t x = seed;
  for (auto& word : state_) word = splitmix64(x);
}

Random Random::stream(std::string_view subsystem) const {
  std::uint64_t mixed = seed_ ^ fnv1a(subsystem);
  return Random(splitmix64(mixed));
}

std::uint64_t Random::next_u64() {
  const std::uint64_t result = std::rotl(state_[1] * 5, 7) * 9;
  const std::uint64_t t = state_[1] << 17;
  state_[2] ^= state_[0];
  state_[3] ^= state_[1];
  state_[1] ^= state_[2];
  state_[0] ^= state_[3];
  state_[2] ^= t;
  state_[3] = std::rotl(state_[3], 45);
  return result;
}

double Random::uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

double Random::uniform(double low, double high) { return low + (high - low) * uniform(); }

double Random::normal(double mean, double stddev) { return mean + stddev * standard_normal(); }

double Random::standard_normal() {
  const Ziggurat& z = ziggurat();
  for (;;) {
    // One draw gives both: the high 53 bits a position in [-1, 1), the low 7 bits the layer
    // (independent bits, as Doornik (2005) advises).
    const std::uint64_t bits = next_u64();
    const double u = static_cast<double>(bits >> 11) * 0x1.0p-52 - 1.0;
    const auto layer = static_cast<std::size_t>(bits & (kZigguratLayers - 1));
    const double x = u * z.x[layer];
    if (std::abs(u) < z.inner[layer]) return x;
    if (layer == 0) {
      // Beyond R: Marsaglia's tail method.
      double beyond = 0.0, height = 0.0;
      do {
        beyond = -std::log(1.0 - uniform()) / kTailStart;
        height = -std::log(1.0 - uniform());
      } while (2.0 * height < beyond * beyond);
      return u < 0.0 ? -(kTailStart + beyond) : kTailStart + beyond;
    }
    // The layer's edge beyond the curve's lowest point in it: under the curve with the density's odds.
    const double below = std::exp(-0.5 * (z.x[layer] * z.x[layer] - x * x));           // f(x[layer]) / f(x)
    const double above = std::exp(-0.5 * (z.x[layer + 1] * z.x[layer + 1] - x * x));   // f(x[layer + 1]) / f(x)
    if (below + uniform() * (above - below) < 1.0) return x;
  }
}

std::string unguessable_id(char prefix) {
  std::random_device device;
  std::string id(1, prefix);
  static constexpr char kHex[] = "0123456789abcdef";
  for (int word = 0; word < 4; ++word) {
    const std::uint32_t bits = device();
    for (int shift = 28; shift >= 0; shift -= 4) id += kHex[(bits >> shift) & 0xF];
  }
  return id;
}

}  // namespace hrisim::core
