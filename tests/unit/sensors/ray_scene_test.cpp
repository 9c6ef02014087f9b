#include "sensors/ray_scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "sensors/laser.hpp"

namespace hrisim::sensors {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<Segment> square_room(double half_side) {
  const double h = half_side;
  return {{{-h, -h}, {h, -h}}, {{h, -h}, {h, h}}, {{h, h}, {-h, h}}, {{-h, h}, {-h, -h}}};
}

TEST(RayScene, ScanOfASquareRoomMatchesGeometry) {
  const auto room = square_room(2.0);
  const RayScene scene(room);
  const BeamFan fan(-kPi, 2.0 * kPi / 720, 720);  // all around
  std::vector<double> ranges(720);
  for (const double heading : {0.0, 0.3, -2.0}) {
    scene.scan(fan, {0.0, 0.0}, heading, 30.0, ranges);
    for (int i = 0; i < 720; ++i) {
      const double angle = heading - kPi + i * 2.0 * kPi / 720;
      const double expected = 2.0 / std::max(std::abs(std::cos(angle)), std::abs(std::sin(angle)));
      ASSERT_NEAR(ranges[i], expected, 1e-9) << "beam " << i << " heading " << heading;
    }
  }
}

TEST(RayScene, NothingWithinRangeReadsInfinity) {
  const auto room = square_room(10.0);
  const RayScene scene(room);
  const BeamFan fan(-0.5, 0.01, 101);
  std::vector<double> ranges(101);
  scene.scan(fan, {0.0, 0.0}, 0.0, 5.0, ranges);
  for (const double range : ranges) EXPECT_EQ(range, std::numeric_limits<double>::infinity());
}

TEST(RayScene, TwoLegsAreTwoArcsAndHideTheWall) {
  const std::vector<Segment> wall{{{3.0, -5.0}, {3.0, 5.0}}};  // 3 m ahead
  RayScene scene(wall);
  // Legs 2 m ahead, 0.2 m apart, radius 0.07 m: the scanner sees two arcs with the wall between.
  scene.add(Circle{{2.0, 0.1}, 0.07});
  scene.add(Circle{{2.0, -0.1}, 0.07});
  const double increment = 0.25 * kPi / 180;
  const BeamFan fan(-kPi * 3 / 4, increment, 1081);
  std::vector<double> ranges(1081);
  scene.scan(fan, {0.0, 0.0}, 0.0, 20.0, ranges);
  std::vector<int> leg_runs;  // lengths of consecutive runs of beams on a leg
  bool on_leg = false;
  for (int i = 0; i < 1081; ++i) {
    const double angle = -kPi * 3 / 4 + i * increment;
    const Vec2 d(std::cos(angle), std::sin(angle));
    double expected = std::abs(d.x()) > 1e-12 && d.x() > 0 ? 3.0 / d.x() : std::numeric_limits<double>::infinity();
    if (std::abs(expected * d.y()) > 5.0) expected = std::numeric_limits<double>::infinity();
    for (const Vec2& leg : {Vec2(2.0, 0.1), Vec2(2.0, -0.1)}) {
      const double along = d.dot(leg), discriminant = 0.07 * 0.07 - (leg.squaredNorm() - along * along);
      if (along > 0 && discriminant >= 0) expected = std::min(expected, along - std::sqrt(discriminant));
    }
    if (std::isinf(expected)) {
      EXPECT_TRUE(std::isinf(ranges[i])) << i;
    } else {
      EXPECT_NEAR(ranges[i], expected, 1e-9) << i;
    }
    const bool leg = ranges[i] < 2.5;
    if (leg && !on_leg) leg_runs.push_back(0);
    if (leg) ++leg_runs.back();
    on_leg = leg;
  }
  ASSERT_EQ(leg_runs.size(), 2u) << "two separate arcs";
  EXPECT_GT(leg_runs[0], 5);
  EXPECT_EQ(leg_runs[0], leg_runs[1]) << "symmetric legs";
}

TEST(RayScene, ArcsAcrossTheFansStartAreFound) {
  // A fan over the full circle starting at angle π (pointing −x); a wall straddling −x.
  const std::vector<Segment> wall{{{-2.0, -1.0}, {-2.0, 1.0}}};
  const RayScene scene(wall);
  const BeamFan fan(kPi, 2.0 * kPi / 360, 360);
  std::vector<double> ranges(360);
  scene.scan(fan, {0.0, 0.0}, 0.0, 10.0, ranges);
  EXPECT_NEAR(ranges[0], 2.0, 1e-9);
  EXPECT_NEAR(ranges[359], 2.0 / std::cos(2.0 * kPi / 360), 1e-9);
  EXPECT_NEAR(ranges[10], 2.0 / std::cos(10 * 2.0 * kPi / 360), 1e-9);
  EXPECT_TRUE(std::isinf(ranges[180]));
}

TEST(RayScene, OneSidedSegmentsAreSeenFromTheirFreeSideOnly) {
  // A solid block from x = 2 to 3: its near face is seen, and from inside the block nothing of it is.
  std::vector<Segment> block;
  world::append_edges({{2, -1}, {3, -1}, {3, 1}, {2, 1}}, block);
  const RayScene scene(block);
  const BeamFan ahead(0.0, 0.0, 1);
  std::vector<double> range(1);
  scene.scan(ahead, {0.0, 0.0}, 0.0, 10.0, range);
  EXPECT_NEAR(range[0], 2.0, 1e-12);
  scene.scan(ahead, {2.5, 0.0}, 0.0, 10.0, range);
  EXPECT_TRUE(std::isinf(range[0]));
  scene.scan(ahead, {5.0, 0.0}, std::numbers::pi, 10.0, range);
  EXPECT_NEAR(range[0], 2.0, 1e-12) << "the far face, from the other side";
}

TEST(Laser, NoiseAndLimitsFollowTheParameters) {
  LaserParams params;  // UST-20LX class
  EXPECT_EQ(params.beams, 1081);
  EXPECT_NEAR(params.increment() * 180 / kPi, 0.25, 1e-12);
  EXPECT_EQ(params.min_range, 0.02);
  EXPECT_EQ(params.max_range, 20.0);
  EXPECT_EQ(params.rate, 40.0);
  const Laser laser(params);
  const std::vector<Segment> wall{{{1.0, -50.0}, {1.0, 50.0}}};
  const RayScene scene(wall);
  core::Random random(3);
  std::vector<double> ranges;
  double sum = 0.0, sum_squares = 0.0;
  int count = 0;
  for (int scan = 0; scan < 20; ++scan) {
    laser.scan(scene, {0.0, 0.0}, 0.0, random, ranges);
    const double error = ranges[540] - 1.0;  // straight ahead
    sum += error;
    sum_squares += error * error;
    ++count;
    for (int i = 0; i < 1081; ++i) {
      const double angle = params.start_angle() + i * params.increment();
      if (std::cos(angle) <= 0.0 || 1.0 / std::cos(angle) > 20.0) {
        EXPECT_TRUE(std::isinf(ranges[i]) && ranges[i] > 0) << i;
      }
    }
  }
  for (int i = 500; i < 580; ++i) {
    sum += ranges[i] - 1.0 / std::cos(params.start_angle() + i * params.increment());
    sum_squares += std::pow(ranges[i] - 1.0 / std::cos(params.start_angle() + i * params.increment()), 2);
    ++count;
  }
  EXPECT_NEAR(sum / count, 0.0, 0.004);
  EXPECT_NEAR(std::sqrt(sum_squares / count), 0.01, 0.003);
  const std::vector<Segment> near_wall{{{0.01, -1.0}, {0.01, 1.0}}};
  const RayScene close(near_wall);
  laser.scan(close, {0.0, 0.0}, 0.0, random, ranges);
  EXPECT_EQ(ranges[540], -std::numeric_limits<double>::infinity()) << "closer than min_range (REP 117)";
}

TEST(Laser, InfraredIsOneBeam) {
  const Laser infrared(infrared_defaults());
  core::Random random(1);
  std::vector<double> ranges;
  const std::vector<Segment> wall{{{0.5, -1.0}, {0.5, 1.0}}};
  infrared.scan(RayScene(wall), {0.0, 0.0}, 0.0, random, ranges);
  ASSERT_EQ(ranges.size(), 1u);
  EXPECT_NEAR(ranges[0], 0.5, 0.05);
  infrared.scan(RayScene(wall), {0.0, 0.0}, kPi, random, ranges);
  EXPECT_TRUE(std::isinf(ranges[0])) << "facing away";
}

}  // namespace
}  // namespace hrisim::sensors
