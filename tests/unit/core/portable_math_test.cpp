#include "core/portable_math.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace hrisim::core {
namespace {

TEST(PortableMath, SinglePrecisionExpMatchesTheLibrary) {
  double worst = 0.0;
  for (float x = -87.0f; x <= 0.0f; x += 0.0131f) {
    worst = std::max(worst, std::abs(exp_nonpositive(x) - std::exp(static_cast<double>(x))) / std::exp(static_cast<double>(x)));
  }
  EXPECT_LT(worst, 3e-7);
  EXPECT_EQ(exp_nonpositive(0.0f), 1.0f);
  EXPECT_EQ(exp_nonpositive(-90.0f), 0.0f);
  EXPECT_NEAR(exp_nonpositive(-std::numbers::ln2_v<float> / 2), 1.0 / std::numbers::sqrt2, 3e-7) << "edge of the reduced range";
}

TEST(PortableMath, Atan2MatchesTheLibraryInEveryQuadrant) {
  double worst = 0.0;
  for (double angle = -std::numbers::pi + 1e-3; angle < std::numbers::pi; angle += 0.001) {
    for (double length : {1e-3, 1.0, 250.0}) {
      const double y = length * std::sin(angle), x = length * std::cos(angle);
      worst = std::max(worst, std::abs(polynomial_atan2(y, x) - std::atan2(y, x)));
    }
  }
  EXPECT_LT(worst, 1e-5);
  EXPECT_NEAR(polynomial_atan2(-0.6f, -0.8f), std::atan2(-0.6, -0.8), 2e-5) << "single precision";
  EXPECT_EQ(polynomial_atan2(0.0, 0.0), 0.0);
  EXPECT_NEAR(polynomial_atan2(1.0, 0.0), std::numbers::pi / 2, 1e-5);
  EXPECT_NEAR(polynomial_atan2(0.0, -1.0), std::numbers::pi, 1e-5);
}

}  // namespace
}  // namespace hrisim::core
