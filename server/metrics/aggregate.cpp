#include "metrics/aggregate.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace hrisim::metrics {
namespace {

// t(0.975, ν) for ν = 1…30, from the standard tables.
constexpr std::array<double, 30> kStudentT95{12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
                                             2.201,  2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
                                             2.080,  2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
constexpr double kNormal975 = 1.959963984540054;

constexpr std::array<std::string_view, 8> kStatistics{"count", "nulls", "mean", "std", "min", "max", "ci95_low", "ci95_high"};

}  // namespace

double student_t95(int degrees) {
  if (degrees < 1) return std::nan("");
  if (degrees <= static_cast<int>(kStudentT95.size())) return kStudentT95[degrees - 1];
  // Cornish–Fisher expansion around the normal quantile; within 1e-4 of the tables beyond 30.
  const double z = kNormal975, v = degrees;
  const double z3 = z * z * z, z5 = z3 * z * z;
  return z + (z3 + z) / (4 * v) + (5 * z5 + 16 * z3 + 3 * z) / (96 * v * v);
}

Aggregate aggregate(std::span<const std::optional<double>> values, bool binary) {
  Aggregate result;
  double sum = 0.0;
  for (const auto& value : values) {
    if (!value) {
      ++result.nulls;
      continue;
    }
    ++result.count;
    sum += *value;
    result.min = result.min ? std::min(*result.min, *value) : *value;
    result.max = result.max ? std::max(*result.max, *value) : *value;
  }
  if (result.count == 0) return result;
  const double n = result.count, mean = sum / n;
  result.mean = mean;
  if (result.count > 1) {
    double squares = 0.0;
    for (const auto& value : values) {
      if (value) squares += (*value - mean) * (*value - mean);
    }
    result.std = std::sqrt(squares / (n - 1));
  }
  if (binary) {
    const double z = kNormal975, z2 = z * z;
    const double centre = (mean + z2 / (2 * n)) / (1 + z2 / n);
    const double half = z / (1 + z2 / n) * std::sqrt(mean * (1 - mean) / n + z2 / (4 * n * n));
    result.ci95_low = std::max(0.0, centre - half);
    result.ci95_high = std::min(1.0, centre + half);
  } else if (result.std) {
    const double half = student_t95(result.count - 1) * *result.std / std::sqrt(n);
    result.ci95_low = mean - half;
    result.ci95_high = mean + half;
  }
  return result;
}

std::optional<double> statistic(const Aggregate& a, std::string_view name) {
  if (name == "count") return a.count;
  if (name == "nulls") return a.nulls;
  if (name == "mean") return a.mean;
  if (name == "std") return a.std;
  if (name == "min") return a.min;
  if (name == "max") return a.max;
  if (name == "ci95_low") return a.ci95_low;
  if (name == "ci95_high") return a.ci95_high;
  return std::nullopt;
}

bool is_statistic(std::string_view name) {
  return std::find(kStatistics.begin(), kStatistics.end(), name) != kStatistics.end();
}

}  // namespace hrisim::metrics
