#include "core/random.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace hrisim::core {
namespace {

TEST(Random, SameSeedSameSequence) {
  Random a(42), b(42), c(43);
  bool differs = false;
  for (int i = 0; i < 1000; ++i) {
    const std::uint64_t x = a.next_u64();
    EXPECT_EQ(x, b.next_u64());
    differs |= x != c.next_u64();
  }
  EXPECT_TRUE(differs);
}

// The generator is part of hrisim's reproducibility promise: these values must never change on any
// platform or compiler (xoshiro256** seeded by SplitMix64 with seed 0).
TEST(Random, GoldenSequence) {
  Random random(0);
  const std::uint64_t first = random.next_u64();
  const std::uint64_t second = random.next_u64();
  Random again(0);
  EXPECT_EQ(again.next_u64(), first);
  EXPECT_EQ(first, 0x99ec5f36cb75f2b4ULL);
  EXPECT_EQ(second, 0xbf6e1f784956452aULL);
}

TEST(Random, StreamsAreIndependentAndReproducible) {
  const Random session(7);
  Random humans = session.stream("humans"), humans_again = session.stream("humans");
  Random robots = session.stream("robots");
  EXPECT_EQ(humans.next_u64(), humans_again.next_u64());
  EXPECT_NE(session.stream("humans").next_u64(), robots.next_u64());
  EXPECT_NE(Random(8).stream("humans").next_u64(), Random(7).stream("humans").next_u64());
}

TEST(Random, UniformMomentsAndRange) {
  Random random(1);
  const int n = 200000;
  double sum = 0.0, sum_squares = 0.0;
  for (int i = 0; i < n; ++i) {
    const double u = random.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    sum_squares += u * u;
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, 0.5, 0.005);
  EXPECT_NEAR(sum_squares / n - mean * mean, 1.0 / 12.0, 0.002);
  for (int i = 0; i < 1000; ++i) {
    const double x = random.uniform(-5.0, 5.0);
    ASSERT_GE(x, -5.0);
    ASSERT_LT(x, 5.0);
  }
}

TEST(Random, NormalMoments) {
  Random random(2);
  const int n = 200000;
  double sum = 0.0, sum_squares = 0.0;
  for (int i = 0; i < n; ++i) {
    const double x = random.normal(1.34, 0.26);
    sum += x;
    sum_squares += x * x;
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, 1.34, 0.005);
  EXPECT_NEAR(std::sqrt(sum_squares / n - mean * mean), 0.26, 0.005);
}

}  // namespace
}  // namespace hrisim::core
