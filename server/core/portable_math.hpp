#pragma once
// exp, atan2, and sin and cos of an angle in turns for inner loops, from polynomials and bit operations only: the same bits on every
// IEEE-754 platform (libm's results may differ between versions and CPUs), inlined, and several times
// faster than the library calls.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace hrisim::core {

// Both are free of branches (selects only), so loops over arrays of them vectorise.

/// e^x for x ≤ 0 in single precision (0 below -87), relative error below 3e-7.
inline float exp_nonpositive(float x) {
  const float clamped = std::max(x, -87.0f);
  // x = k ln2 + r with |r| ≤ ln2 / 2; adding 1.5 × 2^23 rounds to the nearest integer k, which is then
  // the difference of the two numbers' bit patterns.
  constexpr float kRound = 12582912.0f;
  const float shifted = clamped * std::numbers::log2e_v<float> + kRound;
  const float k = shifted - kRound;
  const float r = (clamped - k * 0.693145752f) - k * 1.42860677e-6f;  // ln2 in two parts
  // Taylor series to degree 6 on |r| ≤ 0.347.
  float p = 1.0f / 720.0f;
  p = p * r + 1.0f / 120.0f;
  p = p * r + 1.0f / 24.0f;
  p = p * r + 1.0f / 6.0f;
  p = p * r + 0.5f;
  p = p * r + 1.0f;
  p = p * r + 1.0f;
  const std::uint32_t k_bits = std::bit_cast<std::uint32_t>(shifted) - std::bit_cast<std::uint32_t>(kRound);
  const float scale = std::bit_cast<float>((k_bits + 127) << 23);  // 2^k, a normal number for k ≥ -126
  return x < -87.0f ? 0.0f : p * scale;
}

/// atan2 from a minimax polynomial, |error| < 1e-5 rad; 0 at the origin. For double and float.
template <class Real>
inline Real polynomial_atan2(Real y, Real x) {
  const Real ax = std::abs(x), ay = std::abs(y);
  const Real larger = std::max(ax, ay);
  const Real a = larger > Real(0) ? std::min(ax, ay) / larger : Real(0);
  const Real s = a * a;
  Real r = ((((Real(-0.01172120) * s + Real(0.05265332)) * s - Real(0.11643287)) * s + Real(0.19354346)) * s -
            Real(0.33262347)) * s + Real(0.99997726);
  r *= a;
  constexpr Real kPi = std::numbers::pi_v<Real>;
  r = ay > ax ? kPi / 2 - r : r;
  r = x < Real(0) ? kPi - r : r;
  return y < Real(0) ? -r : r;
}

/// Turns (1 turn = 2π rad) reduce to (-1/2, 1/2] exactly, so large phases (a waveform's) keep their
/// precision better than radians would.
/// sin(2π × turns), |error| < 1e-11.
inline double sin_turns(double turns) {
  double r = turns - std::floor(turns + 0.5);  // exact: [-1/2, 1/2)
  // sin(π - x) = sin(x): fold onto [-1/4, 1/4].
  if (r > 0.25) r = 0.5 - r;
  if (r < -0.25) r = -0.5 - r;
  const double x = 2.0 * std::numbers::pi * r;
  const double x2 = x * x;
  // Taylor series to x^15 on |x| ≤ π/2: the first term left out is below 7e-12.
  double p = -1.0 / 1307674368000.0;
  p = p * x2 + 1.0 / 6227020800.0;
  p = p * x2 - 1.0 / 39916800.0;
  p = p * x2 + 1.0 / 362880.0;
  p = p * x2 - 1.0 / 5040.0;
  p = p * x2 + 1.0 / 120.0;
  p = p * x2 - 1.0 / 6.0;
  p = p * x2 + 1.0;
  return p * x;
}

/// cos(2π × turns).
inline double cos_turns(double turns) { return sin_turns(turns + 0.25); }

}  // namespace hrisim::core
