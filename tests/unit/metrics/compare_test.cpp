// Significance tests against values from statistics tables and textbook examples.
#include "metrics/compare.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace hrisim::metrics {
namespace {

TEST(StudentT, CdfMatchesTheTables) {
  EXPECT_NEAR(student_t_cdf(0.0, 5), 0.5, 1e-12);
  EXPECT_NEAR(student_t_cdf(2.571, 5), 0.975, 1e-4);   // t(0.975, 5)
  EXPECT_NEAR(student_t_cdf(-2.228, 10), 0.025, 1e-4);  // t(0.975, 10)
  EXPECT_NEAR(student_t_cdf(12.706, 1), 0.975, 1e-4);
  EXPECT_NEAR(student_t_cdf(1.96, 1e6), 0.975, 1e-4) << "the normal limit";
}

TEST(Welch, EqualAndDifferentMeans) {
  const std::vector<double> a{1, 2, 3, 4, 5}, same{1, 2, 3, 4, 5}, shifted{11, 12, 13, 14, 15};
  EXPECT_NEAR(*welch_p_value(a, same), 1.0, 1e-12);
  EXPECT_LT(*welch_p_value(a, shifted), 1e-5);
  // Means 3 and 4, both variances 2.5, n = 5: t = −1, 8 degrees of freedom, p = 0.3466.
  const std::vector<double> b{2, 3, 4, 5, 6};
  EXPECT_NEAR(*welch_p_value(a, b), 0.3466, 1e-4);
  EXPECT_FALSE(welch_p_value(std::vector<double>{1}, b)) << "one value has no spread";
  EXPECT_EQ(*welch_p_value(std::vector<double>{2, 2}, std::vector<double>{2, 2, 2}), 1.0);
  EXPECT_EQ(*welch_p_value(std::vector<double>{2, 2}, std::vector<double>{3, 3}), 0.0);
  // A constant metric whose means differ only by rounding is no difference.
  const std::vector<double> constant(3, 2.825);
  const std::vector<double> rounded{2.825, 2.825 + 4e-16, 2.825 - 4e-16, 2.825};
  EXPECT_EQ(*welch_p_value(constant, rounded), 1.0);
}

TEST(Fisher, TheLadyTastingTea) {
  // Fisher's tea-tasting experiment: 3 of 4 right in each group of 4 — two-sided p = 0.4857.
  EXPECT_NEAR(fisher_exact_p_value(3, 4, 1, 4), 0.4857, 1e-4);
  EXPECT_NEAR(fisher_exact_p_value(4, 4, 0, 4), 0.02857, 1e-4);
  EXPECT_NEAR(fisher_exact_p_value(5, 10, 5, 10), 1.0, 1e-12);
  EXPECT_NEAR(fisher_exact_p_value(0, 20, 0, 20), 1.0, 1e-12);
}

TEST(Holm, StepDownAdjustmentAsInHolm1979) {
  // Four tests (one empty): sorted 0.01, 0.02, 0.04 → ×3, ×2, ×1 = 0.03, 0.04, 0.04 (kept non-decreasing).
  const std::vector<std::optional<double>> p{0.04, std::nullopt, 0.01, 0.02};
  const auto adjusted = holm_adjusted(p);
  ASSERT_EQ(adjusted.size(), 4u);
  EXPECT_NEAR(*adjusted[2], 0.03, 1e-15);
  EXPECT_NEAR(*adjusted[3], 0.04, 1e-15);
  EXPECT_NEAR(*adjusted[0], 0.04, 1e-15) << "not below the one before it in order";
  EXPECT_FALSE(adjusted[1]);
  // Capped at 1; ties keep their order.
  const std::vector<std::optional<double>> large{0.6, 0.6, 0.9};
  const auto capped = holm_adjusted(large);
  EXPECT_EQ(*capped[0], 1.0);
  EXPECT_EQ(*capped[1], 1.0);
  EXPECT_EQ(*capped[2], 1.0);
  EXPECT_TRUE(holm_adjusted(std::vector<std::optional<double>>{}).empty());
}

}  // namespace
}  // namespace hrisim::metrics
