#pragma once
// Motion primitives as data (assets/motions/*.json, embedded): keyframes of humanoid_root's
// translation and each joint's orientation over time, interpolated linearly and by slerp — the
// position and orientation interpolators of seed 000 §2.3 — and blended at transitions.
//
// A file: {"name", "description", "duration": s, "loop": bool, "speed": m/s (a clip walked in place),
// "keyframes": [{"time": s, "root": [x, y, z],
// "joints": {"l_shoulder": [rx, ry, rz], …}}]}. Rotations are rotation vectors (axis × angle, rad)
// in the parent joint's frame; joints a keyframe leaves out are at rest. Times start at 0, increase,
// and end at the duration.
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <utility>
#include <vector>

#include "humans/skeleton.hpp"

namespace hrisim::humans {

class MotionClip {
 public:
  /// Reads a motion document; throws core::Error(bad_request) naming the JSON pointer of what is wrong.
  static MotionClip parse(const nlohmann::json& document);

  const std::string& name() const { return name_; }
  double duration() const { return duration_; }
  bool loops() const { return loop_; }
  /// For a clip walked in place (walk): the speed at which its feet do not slide, m/s; 0 otherwise.
  double speed() const { return speed_; }
  /// The pose at time t: wrapped into the clip for a looping clip, held at the ends otherwise.
  SkeletonPose sample(double t) const;

 private:
  std::string name_;
  double duration_ = 0.0;
  bool loop_ = false;
  double speed_ = 0.0;
  std::vector<std::pair<double, SkeletonPose>> keyframes_;
};

/// The pose of a clip walked in place (speed() > 0, e.g. walk) after walking `distance` m: the
/// cycle advances with the distance, not the time, so a planted foot stays put at any walking speed.
SkeletonPose walking_pose(const MotionClip& walk, double distance);

/// Between two poses: weight 0 gives a, 1 gives b (root linearly, joints by slerp).
SkeletonPose blend(const SkeletonPose& a, const SkeletonPose& b, double weight);

/// Names of the motion files shipped in assets/motions/, sorted.
std::vector<std::string> builtin_motion_names();
/// A shipped motion, or nullptr.
const MotionClip* builtin_motion(std::string_view name);

}  // namespace hrisim::humans
