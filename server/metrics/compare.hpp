#pragma once
// Significance tests for comparing two runs metric by metric: Welch's t-test for continuous metrics
// (unequal variances), Fisher's exact test for 0/1 metrics (rates).
#include <optional>
#include <span>
#include <vector>

namespace hrisim::metrics {

/// Differences with a p-value below this are called significant.
inline constexpr double kSignificanceLevel = 0.05;
/// Relative size of spreads and differences taken for rounding, not data.
inline constexpr double kRoundingTolerance = 1e-9;

/// P(T <= t) for Student's t distribution with `degrees` (> 0, may be fractional) degrees of freedom.
double student_t_cdf(double t, double degrees);

/// Two-sided p-value of Welch's t-test that two samples have the same mean; empty with fewer than two
/// values in a sample. Samples without spread (within kRoundingTolerance of their size) give 1 for
/// means equal within that tolerance, 0 otherwise.
std::optional<double> welch_p_value(std::span<const double> a, std::span<const double> b);

/// Two-sided p-value of Fisher's exact test that two groups (hits of total each) have the same rate:
/// the probability of every table with the same margins that is no more likely than the one observed.
double fisher_exact_p_value(int a_hits, int a_total, int b_hits, int b_total);

/// Holm's step-down adjustment of a family of p-values (Holm 1979), which keeps the chance of any false
/// "significant" at the level for the whole family: the k-th smallest of m is multiplied by m − k + 1,
/// then made non-decreasing in that order and capped at 1. Empty p-values are no test: they stay
/// empty and do not count in m.
std::vector<std::optional<double>> holm_adjusted(std::span<const std::optional<double>> p_values);

}  // namespace hrisim::metrics
