#include "robots/motor.hpp"

#include <algorithm>
#include <cmath>

namespace hrisim::robots {

double MotorParams::max_joint_velocity() const { return max_motor_velocity / transmission; }

Motor::Motor(MotorParams params, JointLimits limits, double dt, double initial_position)
    : params_(params),
      limits_(limits),
      dt_(dt),
      delay_ticks_(std::llround((params.kind == MotorKind::dc ? params.dead_time : params.delay) / dt)),
      target_(initial_position),
      position_(initial_position) {
  position_ = clamp_position(position_);
  target_ = position_;
  servo_setpoint_ = position_;
  // The line starts full of "no motion" (DC) or "stay here" (servo) commands.
  delay_line_.assign(static_cast<std::size_t>(delay_ticks_), params_.kind == MotorKind::dc ? 0.0 : position_);
}

double Motor::clamp_position(double position) const {
  if (limits_.lower) position = std::max(position, *limits_.lower);
  if (limits_.upper) position = std::min(position, *limits_.upper);
  return position;
}

void Motor::command_position(double position) {
  mode_ = Mode::position;
  target_ = clamp_position(position);
}

void Motor::command_velocity(double velocity) {
  mode_ = Mode::velocity;
  const std::optional<double> limit =
      params_.kind == MotorKind::dc ? std::optional(params_.max_joint_velocity()) : params_.servo_speed;
  target_ = limit ? std::clamp(velocity, -*limit, *limit) : velocity;
}

void Motor::hash(core::StateHasher& hasher) const {
  hasher.add(position_).add(velocity_).add(controller_velocity_).add(servo_setpoint_).add(static_cast<int>(mode_)).add(target_);
  for (const double queued : delay_line_) hasher.add(queued);
}

void Motor::stop_at(double position, double velocity) {
  position_ = clamp_position(position);
  velocity_ = velocity;
  if (params_.kind == MotorKind::dc) controller_velocity_ = velocity;  // a stalled motor loses its speed
}

void Motor::step(core::Random& random) {
  const double previous = position_;
  if (params_.kind == MotorKind::dc) {
    const double max_velocity = params_.max_joint_velocity();
    // The robot's own loop decides a velocity command now; it reaches the motor after the dead time.
    const double command =
        mode_ == Mode::velocity ? target_ : std::clamp(params_.position_gain * (target_ - position_), -max_velocity, max_velocity);
    delay_line_.push_back(command);
    const double arrived = delay_line_.front();
    delay_line_.pop_front();
    // The velocity loop reaches (1 + gain error) × its command, no faster than the acceleration limit.
    const double wanted = std::clamp((1.0 + params_.gain_error) * arrived, -max_velocity, max_velocity);
    const double step_limit = params_.max_acceleration * dt_;
    controller_velocity_ += std::clamp(wanted - controller_velocity_, -step_limit, step_limit);
    const double noise =
        params_.motor_velocity_noise > 0.0 ? random.normal(0.0, params_.motor_velocity_noise) / params_.transmission : 0.0;
    const double unclamped = position_ + (controller_velocity_ + noise) * dt_;
    position_ = clamp_position(unclamped);
    if (position_ != unclamped) controller_velocity_ = 0.0;  // stopped at a limit
  } else {
    // A servo: the target it is given now is where its internal controller heads after the delay.
    servo_setpoint_ = mode_ == Mode::velocity ? clamp_position(servo_setpoint_ + target_ * dt_) : target_;
    delay_line_.push_back(servo_setpoint_);
    const double arrived = delay_line_.front();
    delay_line_.pop_front();
    if (params_.servo_speed) {
      const double reach = *params_.servo_speed * dt_;
      position_ += std::clamp(arrived - position_, -reach, reach);
    } else {
      position_ = arrived;
    }
  }
  velocity_ = (position_ - previous) / dt_;
}

}  // namespace hrisim::robots
