#pragma once
// People's bodies: each human's skeleton (fixed by its kind of person) posed by what it does now —
// walking at its gait, turning, or playing a motion primitive — as capsules in the map frame, which
// contacts, range sensors and cameras meet.
#include <cstdint>
#include <optional>
#include <vector>

#include "humans/body.hpp"
#include "scenario/model.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// What a human's body is doing now: the inputs of its pose.
humans::Activity activity_of(const scenario::Model& model, const State& state, int agent);

class HumanBodies {
 public:
  explicit HumanBodies(const scenario::Model& model);
  /// The human's capsules now. A body depends on nothing else that changes within a tick, so it is
  /// computed once per tick and place (not for several threads at once).
  const humans::BodyCapsules& of(const scenario::Model& model, const State& state, int agent) const;

 private:
  struct Cached {
    std::int64_t tick = -1;
    Vec2 position = Vec2::Zero();
    double heading = 0.0;
    humans::BodyCapsules body;
  };
  std::vector<std::optional<humans::Skeleton>> skeletons_;  ///< per agent; none for robots
  mutable std::vector<Cached> cache_;
};

}  // namespace hrisim::sim
