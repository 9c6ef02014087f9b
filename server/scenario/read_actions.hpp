#pragma once
// Reading the actions of a native scenario's steps and routines: goto, wait, look_at, turn, publish,
// routine, groups' changes, attitudes, requests, motions, speech, seats and carrying — every
// reference resolved against the names declared and the model's world, each error at its pointer.
#include <optional>
#include <string>

#include "scenario/load_context.hpp"

namespace hrisim::scenario::loading {

class ActionReader {
 public:
  /// `model` has its world, places, agents, objects, groups and clips, and its routines named.
  ActionReader(Context& context, const Model& model);
  /// The action at `pointer`; in a routine (`in_routine`) it names no agent or group.
  Action read(const json& entry, const std::string& pointer, bool in_routine);

 private:
  void read_look_at_object(const json& name, const std::string& pointer, Action& action);
  void read_say(const json& say, const std::string& pointer, Action& action);
  void read_sit_on(const json& sit, const std::string& pointer, Action& action);
  void read_pick_up(const json& pick, const std::string& pointer, Action& action);
  void read_put_down(const json& put, const std::string& pointer, Action& action);
  double acting_radius(const Action& action) const;
  void require_human(const Action& action, const char* what);
  std::optional<Pose2> anchor_of(const Obstacle& obstacle, const std::string& anchor, const std::string& pointer);
  const Obstacle* obstacle_named(const std::string& name, const std::string& pointer);

  Context& context_;
  const Model& model_;
};

}  // namespace hrisim::scenario::loading
