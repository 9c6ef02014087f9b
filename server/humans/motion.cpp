#include "humans/motion.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "core/embedded.hpp"
#include "core/error.hpp"

namespace hrisim::humans::embedded {
extern const std::pair<std::string_view, std::string_view> kEmbedded[];
extern const int kEmbeddedCount;
}  // namespace hrisim::humans::embedded

namespace hrisim::humans {
namespace {

using nlohmann::json;

const std::span<const core::EmbeddedFile> kFiles{embedded::kEmbedded, static_cast<std::size_t>(embedded::kEmbeddedCount)};

[[noreturn]] void bad(const std::string& pointer, const std::string& message) {
  throw core::Error(core::ErrorCode::bad_request, pointer + ": " + message, {{"pointer", pointer}});
}

Eigen::Vector3d vector_of(const json& value, const std::string& pointer) {
  if (!value.is_array() || value.size() != 3 || !std::all_of(value.begin(), value.end(), [](const json& v) { return v.is_number(); })) {
    bad(pointer, "expected three numbers");
  }
  return {value[0].get<double>(), value[1].get<double>(), value[2].get<double>()};
}

Eigen::Quaterniond rotation_of(const Eigen::Vector3d& vector) {
  const double angle = vector.norm();
  if (angle == 0.0) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, vector / angle));
}

}  // namespace

MotionClip MotionClip::parse(const json& document) {
  MotionClip clip;
  if (!document.is_object()) bad("", "a motion is an object");
  if (!document.contains("name") || !document["name"].is_string()) bad("/name", "a name is required");
  if (!document.contains("duration") || !document["duration"].is_number() || !(document["duration"].get<double>() > 0.0)) {
    bad("/duration", "a duration in seconds > 0 is required");
  }
  for (const auto& [key, unused] : document.items()) {
    if (key != "name" && key != "description" && key != "duration" && key != "loop" && key != "speed" && key != "keyframes") {
      bad("/" + key, "unknown field");
    }
  }
  if (document.contains("loop") && !document["loop"].is_boolean()) bad("/loop", "true or false");
  if (document.contains("speed") && (!document["speed"].is_number() || !(document["speed"].get<double>() > 0.0))) {
    bad("/speed", "a speed in m/s > 0");
  }
  clip.speed_ = document.value("speed", 0.0);
  clip.name_ = document["name"];
  clip.duration_ = document["duration"];
  clip.loop_ = document.value("loop", false);
  const json keyframes = document.value("keyframes", json());
  if (!keyframes.is_array() || keyframes.empty()) bad("/keyframes", "at least one keyframe is required");
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    const std::string at = "/keyframes/" + std::to_string(k);
    const json& frame = keyframes[k];
    if (!frame.is_object() || !frame.contains("time") || !frame["time"].is_number()) bad(at + "/time", "a time in seconds is required");
    const double time = frame["time"];
    const double previous = clip.keyframes_.empty() ? -1.0 : clip.keyframes_.back().first;
    if (k == 0 && time != 0.0) bad(at + "/time", "the first keyframe is at time 0");
    if (k > 0 && !(time > previous)) bad(at + "/time", "times must increase");
    if (time > clip.duration_) bad(at + "/time", "after the duration");
    SkeletonPose pose;
    if (frame.contains("root")) pose.root = vector_of(frame["root"], at + "/root");
    const json joints = frame.value("joints", json::object());
    if (!joints.is_object()) bad(at + "/joints", "an object of rotation vectors by joint name");
    for (const auto& [name, value] : joints.items()) {
      const auto joint = joint_by_name(name);
      if (!joint) bad(at + "/joints/" + name, "no joint '" + name + "' at level of articulation 1");
      pose.rotations[static_cast<int>(*joint)] = rotation_of(vector_of(value, at + "/joints/" + name));
    }
    clip.keyframes_.emplace_back(time, pose);
  }
  if (clip.keyframes_.back().first != clip.duration_ && clip.keyframes_.size() > 1) {
    bad("/keyframes/" + std::to_string(keyframes.size() - 1) + "/time", "the last keyframe is at the duration");
  }
  return clip;
}

SkeletonPose MotionClip::sample(double t) const {
  if (loop_) {
    t = std::fmod(t, duration_);
    if (t < 0.0) t += duration_;
  }
  t = std::clamp(t, 0.0, duration_);
  const auto after = std::upper_bound(keyframes_.begin(), keyframes_.end(), t, [](double time, const auto& frame) { return time < frame.first; });
  if (after == keyframes_.begin()) return keyframes_.front().second;
  if (after == keyframes_.end()) return keyframes_.back().second;
  const auto before = std::prev(after);
  return blend(before->second, after->second, (t - before->first) / (after->first - before->first));
}

SkeletonPose walking_pose(const MotionClip& walk, double distance) {
  if (!(walk.speed() > 0.0)) throw core::Error(core::ErrorCode::bad_request, "motion '" + walk.name() + "' is not walked in place (no speed)");
  return walk.sample(distance / walk.speed());
}

SkeletonPose blend(const SkeletonPose& a, const SkeletonPose& b, double weight) {
  if (weight <= 0.0) return a;
  if (weight >= 1.0) return b;
  SkeletonPose pose;
  pose.root = (1.0 - weight) * a.root + weight * b.root;
  for (int j = 0; j < kJointCount; ++j) pose.rotations[j] = a.rotations[j].slerp(weight, b.rotations[j]);
  return pose;
}

std::vector<std::string> builtin_motion_names() { return core::json_file_stems(kFiles); }

const MotionClip* builtin_motion(std::string_view name) {
  // Parsed once, on first use; the shipped files are checked by the tests.
  static const std::map<std::string, MotionClip, std::less<>> clips = [] {
    std::map<std::string, MotionClip, std::less<>> parsed;
    for (const std::string& stem : builtin_motion_names()) {
      parsed.emplace(stem, MotionClip::parse(json::parse(core::find_embedded(kFiles, stem + ".json"))));
    }
    return parsed;
  }();
  const auto found = clips.find(name);
  return found == clips.end() ? nullptr : &found->second;
}

}  // namespace hrisim::humans
