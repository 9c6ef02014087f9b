#pragma once
// Statistics of one metric over the episodes of a run.
#include <optional>
#include <span>
#include <string_view>

namespace hrisim::metrics {

struct Aggregate {
  int count = 0;  ///< episodes with a value
  int nulls = 0;  ///< episodes without one
  std::optional<double> mean, std, min, max;
  /// 95 % confidence interval of the mean: Student's t for continuous metrics, Wilson's score
  /// interval for 0/1 metrics; empty with fewer than two values (one for 0/1 metrics).
  std::optional<double> ci95_low, ci95_high;
};

/// `binary`: the values are 0 or 1 (a rate).
Aggregate aggregate(std::span<const std::optional<double>> values, bool binary);

/// Two-sided 95 % quantile of Student's t distribution with `degrees` degrees of freedom.
double student_t95(int degrees);

/// The statistic of an aggregate by name (count, nulls, mean, std, min, max, ci95_low, ci95_high);
/// empty when it has no value.
std::optional<double> statistic(const Aggregate& aggregate, std::string_view name);
/// Whether `name` is one of the statistics above.
bool is_statistic(std::string_view name);

}  // namespace hrisim::metrics
