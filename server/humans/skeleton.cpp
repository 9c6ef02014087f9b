#include "humans/skeleton.hpp"

#include <algorithm>

namespace hrisim::humans {
namespace {

struct JointInfo {
  std::string_view name;
  Joint parent;
};

constexpr std::array<JointInfo, kJointCount> kJoints{{
    {"humanoid_root", Joint::humanoid_root},
    {"sacroiliac", Joint::humanoid_root},
    {"l_hip", Joint::sacroiliac}, {"l_knee", Joint::l_hip}, {"l_ankle", Joint::l_knee},
    {"r_hip", Joint::sacroiliac}, {"r_knee", Joint::r_hip}, {"r_ankle", Joint::r_knee},
    {"vl5", Joint::sacroiliac}, {"vc7", Joint::vl5}, {"skullbase", Joint::vc7},
    {"l_shoulder", Joint::vc7}, {"l_elbow", Joint::l_shoulder}, {"l_wrist", Joint::l_elbow},
    {"r_shoulder", Joint::vc7}, {"r_elbow", Joint::r_shoulder}, {"r_wrist", Joint::r_elbow},
}};

// Heights of joints as fractions of the standing height (Drillis and Contini).
constexpr double kHipHeight = 0.530, kKneeHeight = 0.285, kAnkleHeight = 0.039, kLumbarHeight = 0.630;
constexpr double kShoulderHeight = 0.818, kElbowHeight = 0.630, kWristHeight = 0.485, kSkullBaseHeight = 0.870;
// Lateral places of joints as fractions of the shoulder width.
constexpr double kShoulderSide = 0.40, kHipSide = 0.20;

}  // namespace

std::string_view joint_name(Joint joint) { return kJoints[static_cast<int>(joint)].name; }

std::optional<Joint> joint_by_name(std::string_view name) {
  const auto found = std::find_if(kJoints.begin(), kJoints.end(), [&](const JointInfo& j) { return j.name == name; });
  if (found == kJoints.end()) return std::nullopt;
  return static_cast<Joint>(found - kJoints.begin());
}

Joint parent(Joint joint) { return kJoints[static_cast<int>(joint)].parent; }

std::optional<BodyDimensions> body_dimensions(std::string_view kind) {
  if (kind == "adult") return kAdultBody;
  if (kind == "child") return kChildBody;
  if (kind == "elder") return kElderBody;
  return std::nullopt;
}

Skeleton::Skeleton(BodyDimensions body) : body_(body) {
  const double h = body.height, w = body.width;
  const auto set = [&](Joint joint, double x, double y, double z) { offsets_[static_cast<int>(joint)] = {x, y, z}; };
  set(Joint::humanoid_root, 0, 0, kHipHeight * h);
  set(Joint::sacroiliac, 0, 0, 0);
  for (const double side : {1.0, -1.0}) {
    const bool left = side > 0;
    set(left ? Joint::l_hip : Joint::r_hip, 0, side * kHipSide * w, 0);
    set(left ? Joint::l_knee : Joint::r_knee, 0, 0, -(kHipHeight - kKneeHeight) * h);
    set(left ? Joint::l_ankle : Joint::r_ankle, 0, 0, -(kKneeHeight - kAnkleHeight) * h);
    set(left ? Joint::l_shoulder : Joint::r_shoulder, 0, side * kShoulderSide * w, 0);
    set(left ? Joint::l_elbow : Joint::r_elbow, 0, 0, -(kShoulderHeight - kElbowHeight) * h);
    set(left ? Joint::l_wrist : Joint::r_wrist, 0, 0, -(kElbowHeight - kWristHeight) * h);
  }
  set(Joint::vl5, 0, 0, (kLumbarHeight - kHipHeight) * h);
  set(Joint::vc7, 0, 0, (kShoulderHeight - kLumbarHeight) * h);
  set(Joint::skullbase, 0, 0, (kSkullBaseHeight - kShoulderHeight) * h);
}

std::array<Eigen::Isometry3d, kJointCount> forward_kinematics(const Skeleton& skeleton, const SkeletonPose& pose,
                                                              const Eigen::Isometry3d& base) {
  std::array<Eigen::Isometry3d, kJointCount> frames;
  // Joints are listed parents first, so one pass suffices.
  for (int j = 0; j < kJointCount; ++j) {
    const auto joint = static_cast<Joint>(j);
    Eigen::Isometry3d local = Eigen::Isometry3d::Identity();
    local.translation() = skeleton.offset(joint) + (joint == Joint::humanoid_root ? pose.root : Eigen::Vector3d::Zero());
    local.linear() = pose.rotations[j].toRotationMatrix();
    frames[j] = (joint == Joint::humanoid_root ? base : frames[static_cast<int>(parent(joint))]) * local;
  }
  return frames;
}

}  // namespace hrisim::humans
