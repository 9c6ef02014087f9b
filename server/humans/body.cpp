#include "humans/body.hpp"

#include <algorithm>
#include <cmath>

namespace hrisim::humans {
namespace {

constexpr std::array<std::string_view, kBodyPartCount> kPartNames{
    "torso", "shoulders", "head", "l_thigh", "l_shin", "l_foot", "r_thigh", "r_shin", "r_foot",
    "l_upper_arm", "l_forearm", "r_upper_arm", "r_forearm"};

// Radii as fractions of the shoulder width.
constexpr double kTorsoRadius = 0.30, kShoulderRadius = 0.13, kThighRadius = 0.16, kShinRadius = 0.11;
constexpr double kUpperArmRadius = 0.10, kForearmRadius = 0.08;
// Head and feet as fractions of the height: the head's sphere centres above the skull base and its
// radius; the foot from behind the ankle to the toes, below it.
constexpr double kHeadLow = 0.025, kHeadHigh = 0.07, kHeadRadius = 0.055;
constexpr double kHeelBack = 0.03, kToeForward = 0.09, kFootDrop = 0.018, kFootRadius = 0.02;
/// The hand continues the forearm past the wrist by this fraction of the height.
constexpr double kHandLength = 0.06;

}  // namespace

std::string_view body_part_name(BodyPart part) { return kPartNames[static_cast<int>(part)]; }

BodyCapsules body_capsules(const Skeleton& skeleton, const std::array<Eigen::Isometry3d, kJointCount>& frames) {
  const double h = skeleton.body().height, w = skeleton.body().width;
  const auto joint = [&](Joint j) -> Eigen::Vector3d { return frames[static_cast<int>(j)].translation(); };
  const auto in_frame = [&](Joint j, double x, double z) -> Eigen::Vector3d { return frames[static_cast<int>(j)] * Eigen::Vector3d(x, 0.0, z); };
  BodyCapsules body;
  const auto set = [&](BodyPart part, const Eigen::Vector3d& from, const Eigen::Vector3d& to, double radius) {
    body[static_cast<int>(part)] = {from, to, radius};
  };
  set(BodyPart::torso, joint(Joint::sacroiliac), joint(Joint::vc7), kTorsoRadius * w);
  set(BodyPart::shoulders, joint(Joint::l_shoulder), joint(Joint::r_shoulder), kShoulderRadius * w);
  set(BodyPart::head, in_frame(Joint::skullbase, 0.0, kHeadLow * h), in_frame(Joint::skullbase, 0.0, kHeadHigh * h), kHeadRadius * h);
  for (const bool left : {true, false}) {
    const Joint hip = left ? Joint::l_hip : Joint::r_hip, knee = left ? Joint::l_knee : Joint::r_knee;
    const Joint ankle = left ? Joint::l_ankle : Joint::r_ankle, shoulder = left ? Joint::l_shoulder : Joint::r_shoulder;
    const Joint elbow = left ? Joint::l_elbow : Joint::r_elbow, wrist = left ? Joint::l_wrist : Joint::r_wrist;
    set(left ? BodyPart::l_thigh : BodyPart::r_thigh, joint(hip), joint(knee), kThighRadius * w);
    set(left ? BodyPart::l_shin : BodyPart::r_shin, joint(knee), joint(ankle), kShinRadius * w);
    set(left ? BodyPart::l_foot : BodyPart::r_foot, in_frame(ankle, -kHeelBack * h, -kFootDrop * h), in_frame(ankle, kToeForward * h, -kFootDrop * h),
        kFootRadius * h);
    set(left ? BodyPart::l_upper_arm : BodyPart::r_upper_arm, joint(shoulder), joint(elbow), kUpperArmRadius * w);
    const Eigen::Vector3d forearm = joint(wrist) - joint(elbow);
    set(left ? BodyPart::l_forearm : BodyPart::r_forearm, joint(elbow), joint(wrist) + kHandLength * h * forearm.normalized(), kForearmRadius * w);
  }
  return body;
}

SkeletonPose body_pose(const Activity& activity) {
  const MotionClip& idle = *builtin_motion("idle");
  const MotionClip& walk = *builtin_motion("walk");
  const double stepping = std::max(std::abs(activity.speed), kTurnStepRadius * std::abs(activity.turn_rate));
  const double gait = std::clamp(stepping / kFullGaitSpeed, 0.0, 1.0);
  // Only the clips that show are sampled.
  SkeletonPose pose = gait >= 1.0   ? walking_pose(walk, activity.gait_distance)
                      : gait <= 0.0 ? idle.sample(activity.time)
                                    : blend(idle.sample(activity.time), walking_pose(walk, activity.gait_distance), gait);
  const double twist = std::clamp(kTurnTwistGain * activity.turn_rate, -kMaxTurnTwist, kMaxTurnTwist);
  if (twist != 0.0) {
    Eigen::Quaterniond& spine = pose.rotations[static_cast<int>(Joint::vl5)];
    spine = Eigen::Quaterniond(Eigen::AngleAxisd(twist, Eigen::Vector3d::UnitZ())) * spine;
  }
  if (!activity.motion) return pose;
  const SkeletonPose played = activity.motion->sample(activity.motion_time);
  const double weight = std::isfinite(activity.since_release) ? 1.0 - activity.since_release / kMotionBlendTime
                                                               : activity.motion_time / kMotionBlendTime;
  return blend(pose, played, std::clamp(weight, 0.0, 1.0));
}

}  // namespace hrisim::humans
