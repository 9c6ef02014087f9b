#pragma once
// The human skeleton: H-Anim joint names at level of articulation 1, body dimensions per kind of
// person (Pedsim's adult, child, elder), and forward kinematics from joint rotations to where every
// joint is (seed 000 §2.3: avatars conforming to H-Anim, motions as joint orientations over time).
//
// Frames follow REP 103: x forward, y left, z up. At rest the person stands upright, arms hanging,
// facing +x, with humanoid_root at the pelvis. A joint's rotation turns everything below it about the
// joint, in its parent's frame.
#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <string_view>

namespace hrisim::humans {

enum class Joint {
  humanoid_root,
  sacroiliac,
  l_hip, l_knee, l_ankle,
  r_hip, r_knee, r_ankle,
  vl5, vc7, skullbase,
  l_shoulder, l_elbow, l_wrist,
  r_shoulder, r_elbow, r_wrist,
};
inline constexpr int kJointCount = static_cast<int>(Joint::r_wrist) + 1;

/// The H-Anim name, e.g. "l_shoulder".
std::string_view joint_name(Joint joint);
std::optional<Joint> joint_by_name(std::string_view name);
/// The joint it hangs from; humanoid_root has none (itself).
Joint parent(Joint joint);

/// A person's size: standing height and shoulder width, m.
struct BodyDimensions {
  double height = 0.0;
  double width = 0.0;
};

// Named defaults (docs): Pedsim's kinds of people.
inline constexpr BodyDimensions kAdultBody{1.75, 0.45};
inline constexpr BodyDimensions kChildBody{1.20, 0.30};
inline constexpr BodyDimensions kElderBody{1.65, 0.44};

/// Dimensions of "adult", "child" or "elder"; empty for another kind.
std::optional<BodyDimensions> body_dimensions(std::string_view kind);

/// The rest pose of one body: each joint's offset from its parent, from anthropometric proportions of
/// the height (Drillis and Contini's segment lengths) and the width.
class Skeleton {
 public:
  explicit Skeleton(BodyDimensions body);
  const BodyDimensions& body() const { return body_; }
  /// Offset of the joint from its parent at rest (of humanoid_root: from the floor below it).
  const Eigen::Vector3d& offset(Joint joint) const { return offsets_[static_cast<int>(joint)]; }

 private:
  BodyDimensions body_;
  std::array<Eigen::Vector3d, kJointCount> offsets_;
};

/// A pose: where humanoid_root is moved from rest, and each joint's rotation (identity: at rest).
struct SkeletonPose {
  Eigen::Vector3d root = Eigen::Vector3d::Zero();
  std::array<Eigen::Quaterniond, kJointCount> rotations;
  SkeletonPose() { rotations.fill(Eigen::Quaterniond::Identity()); }
};

/// Every joint's frame in the world for a person standing at `base` (on the floor, facing its x).
std::array<Eigen::Isometry3d, kJointCount> forward_kinematics(const Skeleton& skeleton, const SkeletonPose& pose,
                                                              const Eigen::Isometry3d& base = Eigen::Isometry3d::Identity());

}  // namespace hrisim::humans
