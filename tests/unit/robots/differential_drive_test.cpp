#include "robots/differential_drive.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace hrisim::robots {
namespace {

TEST(DifferentialDrive, WheelSpeedsAndBodyTwistAreInverse) {
  const DifferentialDriveParams hsr;  // wheel radius 0.04 m, separation 0.266 m
  const WheelSpeeds wheels = wheel_speeds(hsr, {0.2, 0.5});
  EXPECT_NEAR(wheels.left, (0.2 - 0.5 * 0.133) / 0.04, 1e-12);
  EXPECT_NEAR(wheels.right, (0.2 + 0.5 * 0.133) / 0.04, 1e-12);
  const Twist back = body_twist(hsr, wheels);
  EXPECT_NEAR(back.linear, 0.2, 1e-12);
  EXPECT_NEAR(back.angular, 0.5, 1e-12);
}

TEST(DifferentialDrive, LimitsClampEachComponent) {
  const DifferentialDriveParams hsr;
  const Twist limited = limit(hsr, {5.0, -9.0});
  EXPECT_DOUBLE_EQ(limited.linear, 0.8 / 3.6);
  EXPECT_DOUBLE_EQ(limited.angular, -1.0);
}

TEST(DifferentialDrive, ArcIntegrationIsExact) {
  // Driving a full circle in 100 steps comes back to the start; a quarter circle of radius 1 from
  // the origin facing +x ends at (1, 1) facing +y.
  Pose2 pose;
  const Twist circle{1.0, 1.0};
  for (int i = 0; i < 100; ++i) pose = integrate(pose, circle, 2.0 * std::numbers::pi / 100);
  EXPECT_NEAR(pose.x, 0.0, 1e-12);
  EXPECT_NEAR(pose.y, 0.0, 1e-12);
  const Pose2 quarter = integrate({}, circle, std::numbers::pi / 2);
  EXPECT_NEAR(quarter.x, 1.0, 1e-12);
  EXPECT_NEAR(quarter.y, 1.0, 1e-12);
  EXPECT_NEAR(quarter.theta, std::numbers::pi / 2, 1e-12);
  const Pose2 straight = integrate({1.0, 2.0, std::numbers::pi / 2}, {0.5, 0.0}, 2.0);
  EXPECT_NEAR(straight.x, 1.0, 1e-12);
  EXPECT_NEAR(straight.y, 3.0, 1e-12);
}

}  // namespace
}  // namespace hrisim::robots
