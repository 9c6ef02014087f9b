#pragma once
// Joint actuators as SimVis3D models them (seed 000 §2.1): a DC motor behind a velocity controller
// (transmission, controller gain error and noise, dead time, velocity and acceleration limits), and a
// servo with an internal position controller (its speed limited, no noise). Both take the same commands — a
// position or a velocity target — so a controller does not know which motor sits behind a joint.
// Deterministic: time advances in whole ticks, noise comes from the caller's seeded generator.
#include <cstdint>
#include <deque>
#include <optional>

#include "core/random.hpp"
#include "core/state_hash.hpp"

namespace hrisim::robots {

enum class MotorKind { dc, servo };

/// Named defaults of the motor models (documented in docs/robots/motors.md).
inline constexpr double kDefaultTransmission = 1.0;       ///< motor rad per joint unit
inline constexpr double kDefaultMaxAcceleration = 10.0;   ///< joint units/s²
inline constexpr double kDefaultPositionGain = 4.0;       ///< 1/s: a DC joint's position loop
inline constexpr double kDefaultDeadTime = 0.0;           ///< s
inline constexpr double kDefaultServoDelay = 0.0;         ///< s

struct MotorParams {
  MotorKind kind = MotorKind::dc;
  double transmission = kDefaultTransmission;  ///< gear ratio: motor rad per joint rad (or per joint m)
  double max_motor_velocity = 1.0;             ///< DC: at the motor, rad/s; the joint's is this / transmission
  double max_acceleration = kDefaultMaxAcceleration;  ///< DC: at the joint, units/s²
  double gain_error = 0.0;           ///< DC: the velocity controller reaches (1 + gain_error) × its command
  double motor_velocity_noise = 0.0; ///< DC: standard deviation of the motor's velocity, rad/s
  double dead_time = kDefaultDeadTime;  ///< DC: a command takes effect this long after it is given, s
  double position_gain = kDefaultPositionGain;  ///< DC: velocity command = gain × position error
  double delay = kDefaultServoDelay;  ///< servo: a position command takes effect this long after, s
  std::optional<double> servo_speed;  ///< servo: joint units/s towards the target; instant when absent

  /// The joint's velocity limit, units/s.
  double max_joint_velocity() const;
};

/// Travel limits of the joint a motor drives; none for continuous joints and wheels.
struct JointLimits {
  std::optional<double> lower, upper;
};

/// One motor and the joint it drives: command in, position and velocity out, once per tick.
class Motor {
 public:
  Motor(MotorParams params, JointLimits limits, double dt, double initial_position = 0.0);

  /// Hold this joint position (clamped to the limits).
  void command_position(double position);
  /// Move at this joint velocity (clamped to the limit) until told otherwise.
  void command_velocity(double velocity);

  /// Advances one tick of dt; noise from `random`.
  void step(core::Random& random);
  /// The joint was stopped short by something solid: it stands at `position`, moving at `velocity`.
  void stop_at(double position, double velocity);

  double position() const { return position_; }
  double velocity() const { return velocity_; }
  const MotorParams& params() const { return params_; }
  const JointLimits& limits() const { return limits_; }

  /// Everything that changes, for state hashes.
  void hash(core::StateHasher& hasher) const;

 private:
  enum class Mode { position, velocity };
  double clamp_position(double position) const;

  MotorParams params_;
  JointLimits limits_;
  double dt_;
  std::int64_t delay_ticks_;  ///< the dead time (DC) or delay (servo) in whole ticks
  Mode mode_ = Mode::position;
  double target_;  ///< position or velocity, by mode
  /// Commands on their way to the motor, oldest first (DC: velocities; servo: positions).
  std::deque<double> delay_line_;
  double position_;
  double velocity_ = 0.0;
  double controller_velocity_ = 0.0;  ///< DC: the velocity loop's output before noise
  double servo_setpoint_ = 0.0;       ///< servo: the newest position given to it
};

}  // namespace hrisim::robots
