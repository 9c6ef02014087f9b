#include "metrics/compare.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hrisim::metrics {
namespace {

/// Continued fraction of the regularized incomplete beta function (modified Lentz's method).
double beta_fraction(double a, double b, double x) {
  constexpr double kTiny = 1e-300, kEpsilon = 1e-15;
  constexpr int kIterations = 300;
  double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::abs(d) < kTiny) d = kTiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m <= kIterations; ++m) {
    const double m2 = 2.0 * m;
    // Even step, then odd step of the fraction.
    for (const double numerator : {m * (b - m) * x / ((a + m2 - 1.0) * (a + m2)), -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0))}) {
      d = 1.0 + numerator * d;
      if (std::abs(d) < kTiny) d = kTiny;
      c = 1.0 + numerator / c;
      if (std::abs(c) < kTiny) c = kTiny;
      d = 1.0 / d;
      h *= d * c;
    }
    if (std::abs(d * c - 1.0) < kEpsilon) break;
  }
  return h;
}

/// I_x(a, b), the regularized incomplete beta function.
double incomplete_beta(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x));
  // The fraction converges fast below the mean; use the symmetry I_x(a, b) = 1 − I_{1−x}(b, a) above it.
  if (x < (a + 1.0) / (a + b + 2.0)) return front * beta_fraction(a, b, x) / a;
  return 1.0 - front * beta_fraction(b, a, 1.0 - x) / b;
}

double mean_of(std::span<const double> values) { return std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size()); }

double variance_of(std::span<const double> values, double mean) {
  double squares = 0.0;
  for (const double v : values) squares += (v - mean) * (v - mean);
  return squares / static_cast<double>(values.size() - 1);
}

/// log of the hypergeometric probability of a table with `hits` in the first group.
double log_table_probability(int hits, int a_total, int b_total, int all_hits) {
  const auto log_choose = [](int n, int k) { return std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0); };
  return log_choose(a_total, hits) + log_choose(b_total, all_hits - hits) - log_choose(a_total + b_total, all_hits);
}

}  // namespace

double student_t_cdf(double t, double degrees) {
  const double tail = 0.5 * incomplete_beta(degrees / 2.0, 0.5, degrees / (degrees + t * t));
  return t >= 0.0 ? 1.0 - tail : tail;
}

std::optional<double> welch_p_value(std::span<const double> a, std::span<const double> b) {
  if (a.size() < 2 || b.size() < 2) return std::nullopt;
  const double mean_a = mean_of(a), mean_b = mean_of(b);
  const double va = variance_of(a, mean_a) / static_cast<double>(a.size()), vb = variance_of(b, mean_b) / static_cast<double>(b.size());
  // Spread and difference within rounding of the values' size count as none: constant metrics
  // averaged over different numbers of episodes differ in the last bits.
  const double scale = std::max({std::abs(mean_a), std::abs(mean_b), 1.0}) * kRoundingTolerance;
  if (std::sqrt(va + vb) <= scale) return std::abs(mean_a - mean_b) <= scale ? 1.0 : 0.0;
  const double t = (mean_a - mean_b) / std::sqrt(va + vb);
  // Welch–Satterthwaite degrees of freedom.
  const double degrees = (va + vb) * (va + vb) / (va * va / static_cast<double>(a.size() - 1) + vb * vb / static_cast<double>(b.size() - 1));
  return 2.0 * student_t_cdf(-std::abs(t), degrees);
}

double fisher_exact_p_value(int a_hits, int a_total, int b_hits, int b_total) {
  const int all_hits = a_hits + b_hits;
  const int lowest = std::max(0, all_hits - b_total), highest = std::min(a_total, all_hits);
  const double observed = log_table_probability(a_hits, a_total, b_total, all_hits);
  double p = 0.0;
  for (int hits = lowest; hits <= highest; ++hits) {
    const double log_p = log_table_probability(hits, a_total, b_total, all_hits);
    // Tables as likely as the observed one count too (a relative tolerance for rounding).
    if (log_p <= observed + 1e-7) p += std::exp(log_p);
  }
  return std::min(1.0, p);
}

std::vector<std::optional<double>> holm_adjusted(std::span<const std::optional<double>> p_values) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < p_values.size(); ++i) {
    if (p_values[i]) order.push_back(i);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return *p_values[a] < *p_values[b]; });
  std::vector<std::optional<double>> adjusted(p_values.size());
  const double tests = static_cast<double>(order.size());
  double running = 0.0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    running = std::max(running, std::min(1.0, (tests - static_cast<double>(k)) * *p_values[order[k]]));
    adjusted[order[k]] = running;
  }
  return adjusted;
}

}  // namespace hrisim::metrics
