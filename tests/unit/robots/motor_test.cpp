#include "robots/motor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace hrisim::robots {
namespace {

constexpr double kDt = 1.0 / 60.0;

MotorParams dc_motor() {
  MotorParams params;
  params.kind = MotorKind::dc;
  params.transmission = 100.0;
  params.max_motor_velocity = 200.0;  // 2 units/s at the joint
  params.max_acceleration = 1000.0;   // effectively instant
  return params;
}

TEST(Motor, DcVelocityCommandTakesEffectAfterTheDeadTime) {
  MotorParams params = dc_motor();
  params.dead_time = 5 * kDt;
  Motor motor(params, {}, kDt);
  core::Random random(1);
  motor.command_velocity(1.0);
  for (int tick = 1; tick <= 5; ++tick) {
    motor.step(random);
    EXPECT_EQ(motor.velocity(), 0.0) << "tick " << tick << ": still inside the dead time";
  }
  motor.step(random);
  EXPECT_NEAR(motor.velocity(), 1.0, 1e-12) << "the command arrives on the sixth tick";
}

TEST(Motor, DcRespectsVelocityAndAccelerationLimits) {
  MotorParams params = dc_motor();
  params.max_acceleration = 3.0;
  Motor motor(params, {}, kDt);
  core::Random random(1);
  motor.command_velocity(50.0);  // far above the 2 units/s limit
  double previous = 0.0;
  for (int tick = 0; tick < 120; ++tick) {
    motor.step(random);
    EXPECT_LE(motor.velocity(), 2.0 + 1e-12);
    EXPECT_LE(motor.velocity() - previous, 3.0 * kDt + 1e-12) << "tick " << tick;
    previous = motor.velocity();
  }
  EXPECT_NEAR(motor.velocity(), 2.0, 1e-12) << "reaches the limit after 2/3 s";
}

TEST(Motor, DcGainErrorScalesTheReachedVelocity) {
  MotorParams params = dc_motor();
  params.gain_error = 0.05;
  Motor motor(params, {}, kDt);
  core::Random random(1);
  motor.command_velocity(1.0);
  for (int tick = 0; tick < 10; ++tick) motor.step(random);
  EXPECT_NEAR(motor.velocity(), 1.05, 1e-12);
}

TEST(Motor, DcNoiseHasTheConfiguredSpreadAtTheJoint) {
  MotorParams params = dc_motor();
  params.motor_velocity_noise = 10.0;  // rad/s at the motor → 0.1 units/s at the joint
  Motor motor(params, {}, kDt);
  core::Random random(7);
  motor.command_velocity(1.0);
  for (int tick = 0; tick < 10; ++tick) motor.step(random);
  double sum = 0.0, sum_squares = 0.0;
  const int samples = 20000;
  for (int i = 0; i < samples; ++i) {
    motor.step(random);
    sum += motor.velocity();
    sum_squares += motor.velocity() * motor.velocity();
  }
  const double mean = sum / samples;
  const double spread = std::sqrt(sum_squares / samples - mean * mean);
  EXPECT_NEAR(mean, 1.0, 0.005);
  EXPECT_NEAR(spread, 0.1, 0.005);
}

TEST(Motor, DcPositionModeSettlesOnTheTargetAndStopsAtLimits) {
  Motor motor(dc_motor(), {-1.0, 1.5}, kDt);
  core::Random random(1);
  motor.command_position(0.8);
  for (int tick = 0; tick < 600; ++tick) motor.step(random);
  EXPECT_NEAR(motor.position(), 0.8, 1e-6);
  motor.command_position(4.0);  // clamped to the upper limit
  for (int tick = 0; tick < 600; ++tick) motor.step(random);
  EXPECT_NEAR(motor.position(), 1.5, 1e-6);
  motor.command_velocity(-2.0);
  for (int tick = 0; tick < 600; ++tick) {
    motor.step(random);
    EXPECT_GE(motor.position(), -1.0);
  }
  EXPECT_EQ(motor.position(), -1.0);
}

TEST(Motor, ServoFollowsItsPositionCommandAfterTheDelayOnly) {
  MotorParams params;
  params.kind = MotorKind::servo;
  params.delay = 3 * kDt;
  Motor motor(params, {-1.0, 1.0}, kDt, 0.2);
  core::Random random(1);
  motor.command_position(0.7);
  for (int tick = 1; tick <= 3; ++tick) {
    motor.step(random);
    EXPECT_EQ(motor.position(), 0.2) << "tick " << tick;
  }
  motor.step(random);
  EXPECT_EQ(motor.position(), 0.7) << "no dynamics beyond the delay";
}

TEST(Motor, ServoTakesVelocityCommandsThroughTheSameInterface) {
  MotorParams params;
  params.kind = MotorKind::servo;
  params.servo_speed = 1.0;
  Motor motor(params, {-1.0, 1.0}, kDt);
  core::Random random(1);
  motor.command_velocity(3.0);  // clamped to the servo's speed
  for (int tick = 0; tick < 30; ++tick) motor.step(random);
  EXPECT_NEAR(motor.position(), 0.5, 1e-9);
  EXPECT_NEAR(motor.velocity(), 1.0, 1e-9);
}

TEST(Motor, SameSeedSameMotion) {
  MotorParams params = dc_motor();
  params.motor_velocity_noise = 5.0;
  params.dead_time = 0.05;
  auto run = [&](std::uint64_t seed) {
    Motor motor(params, {}, kDt);
    core::Random random(seed);
    motor.command_velocity(1.0);
    for (int tick = 0; tick < 100; ++tick) motor.step(random);
    return motor.position();
  };
  EXPECT_EQ(run(3), run(3));
  EXPECT_NE(run(3), run(4));
}

}  // namespace
}  // namespace hrisim::robots
