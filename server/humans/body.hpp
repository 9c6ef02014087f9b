#pragma once
// A person's body as solids and the pose it takes. The solids are capsules between the skeleton's
// joints, so whatever touches or sees a person — contact in the physics world, laser returns,
// rendered frames — meets the animated body. The pose comes from what the person does: standing,
// walking with the gait cycle advanced by the distance walked (feet do not slide at any speed),
// leaning into turns, or playing a motion primitive, with blends at the transitions.
#include <array>
#include <limits>
#include <string_view>

#include "humans/motion.hpp"
#include "humans/skeleton.hpp"

namespace hrisim::humans {

enum class BodyPart {
  torso, shoulders, head,
  l_thigh, l_shin, l_foot, r_thigh, r_shin, r_foot,
  l_upper_arm, l_forearm, r_upper_arm, r_forearm,
};
inline constexpr int kBodyPartCount = static_cast<int>(BodyPart::r_forearm) + 1;

std::string_view body_part_name(BodyPart part);

/// A solid: the segment between two points swept by a sphere of `radius`, m, in the map frame.
struct Capsule {
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
  double radius = 0.0;
};

using BodyCapsules = std::array<Capsule, kBodyPartCount>;

/// The body's solids for joint frames from forward_kinematics. Radii are fractions of the shoulder
/// width (limbs, torso) or of the height (head, feet), so a child is slimmer than an adult.
BodyCapsules body_capsules(const Skeleton& skeleton, const std::array<Eigen::Isometry3d, kJointCount>& frames);

// Named defaults (docs): how motions are put together.
/// Time over which a motion primitive blends in from walking or standing, and back out, s.
inline constexpr double kMotionBlendTime = 0.3;
/// At this speed and above a person walks the full gait; slower, it blends towards standing, m/s.
inline constexpr double kFullGaitSpeed = 0.3;
/// Turning on the spot, the feet step as if walking this far per radian turned, m/rad.
inline constexpr double kTurnStepRadius = 0.15;
/// The upper body leans into a turn by this many radians of twist per rad/s of turn rate...
inline constexpr double kTurnTwistGain = 0.25;
/// ...up to this twist, rad.
inline constexpr double kMaxTurnTwist = 0.35;

/// What a person's body is doing: everything its pose depends on.
struct Activity {
  double time = 0.0;           ///< s since the start (idle breathing)
  double gait_distance = 0.0;  ///< m walked, plus stepping while turning: the gait cycle's position
  double speed = 0.0;          ///< m/s now
  double turn_rate = 0.0;      ///< rad/s now, positive to the left
  const MotionClip* motion = nullptr;  ///< a primitive played (its last pose held when it ends), or none
  double motion_time = 0.0;            ///< s since it started (frozen once it is released)
  /// s since the person left the primitive (started walking); it blends out over kMotionBlendTime.
  double since_release = std::numeric_limits<double>::infinity();
};

/// The pose for an activity (joint rotations and root offset; the person's place and heading are
/// the base of forward_kinematics).
SkeletonPose body_pose(const Activity& activity);

}  // namespace hrisim::humans
