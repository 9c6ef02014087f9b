#pragma once
// Activity models (seed 000, SimVis3D's HRI extension): a person who lives on their own picks what to
// do next — a motion primitive, a walk to one of some places, a pause — by a Markov chain, with
// transition probabilities per type of person (adult, child, elder). A chain is checked for what a
// body can do next: a person who has fallen gets up before walking, a seated one stands up first.
// ("Behaviour" is kept for HuNavSim's reactions to a robot: an activity is what someone does.)
#include <map>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "core/json_schema.hpp"
#include "humans/motion.hpp"

namespace hrisim::scenario {

/// How a body rests: what it must be in to start a motion, and what a motion leaves it in.
enum class Posture { standing, seated, lying };

/// A motion's posture at its start or end, by how far it lowers the body's root: less than
/// kSeatedRootDrop is standing, less than kLyingRootDrop seated, lying beyond, m.
inline constexpr double kSeatedRootDrop = 0.25;
inline constexpr double kLyingRootDrop = 0.6;
Posture posture_at(const humans::MotionClip& clip, double time);

struct Activity {
  enum class Kind { motion, walk, wait, turn };
  std::string name;
  Kind kind = Kind::wait;
  std::string motion;          ///< motion: a shipped primitive
  std::vector<int> locations;  ///< walk: one is drawn, each equally likely
  double min_duration = 0.0;   ///< motion, wait: the duration is drawn uniformly in [min, max], s
  double max_duration = 0.0;
  double min_angle = 0.0;      ///< turn: the angle is drawn uniformly in [min, max], rad (positive: to the left)
  double max_angle = 0.0;
};

/// Transition probabilities: row i gives the next activity's probabilities after activity i.
using TransitionMatrix = std::vector<std::vector<double>>;

struct ActivityModel {
  std::string name;
  std::vector<Activity> activities;
  int start = 0;  ///< the first activity, begun standing
  TransitionMatrix transitions;
  std::map<std::string, TransitionMatrix> transitions_by_type;  ///< a type of person's own chain

  const TransitionMatrix& transitions_for(const std::string& type) const;
};

/// Reads the scenario's "activity_models" (already checked against the schema) with their meaning:
/// motions and places exist, every row adds up to 1, no transition asks a body for what it cannot
/// do next, and every activity can be left and leads back to the start. Errors carry JSON pointers.
std::vector<ActivityModel> read_activity_models(const nlohmann::json& models, const std::map<std::string, int>& locations,
                                                std::vector<core::ValidationError>& errors);

}  // namespace hrisim::scenario
