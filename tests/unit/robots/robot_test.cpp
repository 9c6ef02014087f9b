#include "robots/robot.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "core/error.hpp"

namespace hrisim::robots {
namespace {

constexpr double kDt = 1.0 / 60.0;

TEST(Robot, HsrDrivesWhereItsWheelsTakeIt) {
  Robot hsr(builtin_robot("hsr"), {1.0, 2.0, 0.0}, kDt);
  core::Random random(1);
  hsr.command_base({0.2, 0.0});
  for (int tick = 0; tick < 300; ++tick) hsr.step(random);  // 5 s
  // 0.2 m/s for 5 s, less one tick of dead time and half the ramp: wheels reach 0.2 / 0.04 = 5 rad/s
  // at 25 rad/s² in 0.2 s. The wheel noise averages out.
  const double expected = 1.0 + 0.2 * (5.0 - kDt - 0.5 * 0.2);
  EXPECT_NEAR(hsr.pose().x, expected, 0.005);
  EXPECT_NEAR(hsr.pose().y, 2.0, 0.005);
  EXPECT_NEAR(hsr.twist().linear, 0.2, 0.01);
  hsr.command_base({5.0, 0.0});
  for (int tick = 0; tick < 120; ++tick) hsr.step(random);
  EXPECT_LT(hsr.twist().linear, 0.8 / 3.6 + 0.01) << "0.8 km/h at most";
  hsr.command_base({0.0, 0.5});
  const double heading = hsr.pose().theta;
  for (int tick = 0; tick < 120; ++tick) hsr.step(random);
  EXPECT_NEAR(core::wrap_angle(hsr.pose().theta - heading), 0.95, 0.08) << "turning on the spot for 2 s";
}

TEST(Robot, ArmGroupReachesItsTargetsWithinTheLimits) {
  Robot hsr(builtin_robot("hsr"), {}, kDt);
  core::Random random(1);
  const std::vector<double> targets{0.5, -1.0, 0.3, -0.5, 1.0, 0.2};
  hsr.command_group("arm", targets);
  for (int tick = 0; tick < 600; ++tick) hsr.step(random);
  const auto& arm = hsr.description().groups.at("arm");
  for (std::size_t i = 0; i < arm.size(); ++i) {
    EXPECT_NEAR(hsr.joint_position(hsr.joint_index(arm[i])), targets[i], 0.01) << arm[i];
  }
  // The torso follows the arm lift at half its travel.
  EXPECT_NEAR(hsr.joint_position(hsr.joint_index("torso_lift_joint")), 0.25, 0.005);
  hsr.command_group("arm", std::vector<double>{5.0, -9.0, 0.0, 0.0, 0.0, 0.0});
  for (int tick = 0; tick < 900; ++tick) hsr.step(random);
  EXPECT_LE(hsr.joint_position(hsr.joint_index("arm_lift_joint")), 0.69);
  EXPECT_GE(hsr.joint_position(hsr.joint_index("arm_flex_joint")), -150.11 * std::numbers::pi / 180 - 1e-12);
  EXPECT_THROW(hsr.command_group("arm", std::vector<double>{1.0}), core::Error);
  EXPECT_THROW(hsr.command_group("legs", std::vector<double>{1.0}), core::Error);
  EXPECT_THROW(hsr.joint_index("tail_joint"), core::Error);
}

TEST(Robot, ForwardKinematicsPutsTheHeadAtTheSeedsHeights) {
  Robot hsr(builtin_robot("hsr"), {}, kDt);
  core::Random random(1);
  const int tilt = hsr.description().find_link("head_tilt_link");
  const double low = hsr.link_poses()[tilt].translation().z();
  hsr.command_group("arm", std::vector<double>{0.69, 0.0, 0.0, 0.0, 0.0, 0.0});
  for (int tick = 0; tick < 600; ++tick) hsr.step(random);
  const double high = hsr.link_poses()[tilt].translation().z();
  EXPECT_NEAR(high - low, 0.345, 1e-3) << "the neck extends 34.5 cm";
  const Eigen::Vector3d laser = hsr.sensor_pose(*hsr.description().find_sensor("base_scan")).translation();
  // Within the base roll joint's noise around its held position.
  EXPECT_NEAR(laser.x(), 0.1675, 1e-3);
  EXPECT_NEAR(laser.z(), 0.1844, 1e-9);
}

TEST(Robot, GripperOpensAndCloses) {
  Robot hsr(builtin_robot("hsr"), {}, kDt);
  core::Random random(1);
  const int motor = hsr.joint_index("hand_motor_joint");
  const int mirror = hsr.joint_index("hand_r_proximal_joint");
  hsr.set_gripper(false);
  for (int tick = 0; tick < 300; ++tick) hsr.step(random);
  EXPECT_NEAR(hsr.joint_position(motor), 71.04 * std::numbers::pi / 180, 0.01);
  EXPECT_EQ(hsr.joint_position(mirror), hsr.joint_position(motor));
  hsr.set_gripper(true);
  EXPECT_TRUE(hsr.gripper_closed());
  for (int tick = 0; tick < 300; ++tick) hsr.step(random);
  EXPECT_NEAR(hsr.joint_position(motor), -45.72 * std::numbers::pi / 180, 0.01);
}

TEST(Robot, RomanHasNoDriveAndServoEyes) {
  Robot roman(builtin_robot("roman"), {}, kDt);
  core::Random random(1);
  try {
    roman.command_base({0.1, 0.0});
    FAIL() << "ROMAN stands on a fixed stand";
  } catch (const core::Error& error) {
    EXPECT_EQ(error.code(), core::ErrorCode::conflict);
  }
  EXPECT_THROW(roman.set_gripper(true), core::Error);
  roman.command_group("eyes", std::vector<double>{0.3, 0.3, 0.0, 0.0});
  roman.step(random);
  roman.step(random);
  EXPECT_EQ(roman.joint_position(roman.joint_index("left_eye_pan_joint")), 0.0) << "servo delay of 0.05 s (3 ticks)";
  for (int tick = 0; tick < 60; ++tick) roman.step(random);
  EXPECT_NEAR(roman.joint_position(roman.joint_index("left_eye_pan_joint")), 0.3, 1e-12);
}

TEST(Robot, SameSeedSameHash) {
  auto run = [](std::uint64_t seed) {
    Robot artos(builtin_robot("artos"), {}, kDt);
    core::Random random(seed);
    artos.command_base({0.5, 0.3});
    for (int tick = 0; tick < 200; ++tick) artos.step(random);
    core::StateHasher hasher;
    artos.hash(hasher);
    return hasher.value();
  };
  EXPECT_EQ(run(1), run(1));
  EXPECT_NE(run(1), run(2));
}

}  // namespace
}  // namespace hrisim::robots
