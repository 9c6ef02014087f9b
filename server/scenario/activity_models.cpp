#include "scenario/activity_models.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>

#include "humans/skeleton.hpp"

namespace hrisim::scenario {
namespace {

using nlohmann::json;
using Errors = std::vector<core::ValidationError>;

/// Rows may be off by rounding in the file's decimals, not more.
constexpr double kRowSumTolerance = 1e-6;

const char* posture_name(Posture posture) {
  switch (posture) {
    case Posture::standing: return "standing";
    case Posture::seated: return "seated";
    case Posture::lying: return "lying";
  }
  return "standing";
}

/// Postures as bits of a set.
unsigned bit(Posture posture) { return 1u << static_cast<unsigned>(posture); }

/// The posture an activity needs to begin, if it needs one (a pause keeps whatever the body is in).
std::optional<Posture> needs(const Activity& activity) {
  if (activity.kind == Activity::Kind::walk || activity.kind == Activity::Kind::turn) return Posture::standing;
  if (activity.kind == Activity::Kind::motion) return posture_at(*humans::builtin_motion(activity.motion), 0.0);
  return std::nullopt;
}

/// The postures an activity leaves the body in, begun in any of `entered`.
unsigned leaves(const Activity& activity, unsigned entered) {
  if (activity.kind == Activity::Kind::walk || activity.kind == Activity::Kind::turn) return bit(Posture::standing);
  if (activity.kind == Activity::Kind::motion) {
    const humans::MotionClip& clip = *humans::builtin_motion(activity.motion);
    return bit(posture_at(clip, clip.duration()));
  }
  return entered;
}

std::string known_motions() {
  std::string names;
  for (const std::string& name : humans::builtin_motion_names()) names += (names.empty() ? "" : ", ") + name;
  return names;
}

class ModelReader {
 public:
  ModelReader(const std::string& pointer, const std::map<std::string, int>& locations, Errors& errors)
      : pointer_(pointer), locations_(locations), errors_(errors) {}

  ActivityModel read(const std::string& name, const json& entry) {
    ActivityModel model;
    model.name = name;
    const json& activities = entry.at("activities");
    for (const auto& [activity_name, definition] : activities.items()) {
      index_[activity_name] = static_cast<int>(model.activities.size());
      model.activities.push_back(read_activity(activity_name, definition));
    }
    const std::string start = entry.at("start");
    if (!index_.contains(start)) {
      error("/start", "'" + start + "' is not one of the model's activities");
    } else {
      model.start = index_.at(start);
    }
    const std::size_t errors_before = errors_.size();
    model.transitions = read_transitions(model, entry.at("transitions"), "/transitions");
    if (entry.contains("transitions_by_type")) {
      for (const auto& [type, matrix] : entry["transitions_by_type"].items()) {
        const std::string at = "/transitions_by_type/" + core::pointer_token(type);
        if (!humans::body_dimensions(type)) {
          error(at, "'" + type + "' is not a type of person (adult, child or elder)");
          continue;
        }
        model.transitions_by_type[type] = read_transitions(model, matrix, at);
      }
    }
    if (errors_.size() != errors_before) return model;  // the chains are checked once their rows read
    check_chain(model, model.transitions, "/transitions");
    for (const auto& [type, matrix] : model.transitions_by_type) check_chain(model, matrix, "/transitions_by_type/" + core::pointer_token(type));
    return model;
  }

 private:
  void error(const std::string& at, const std::string& message) { errors_.push_back({pointer_ + at, message}); }

  Activity read_activity(const std::string& name, const json& definition) {
    const std::string at = "/activities/" + core::pointer_token(name);
    Activity activity;
    activity.name = name;
    if (definition.contains("motion")) {
      activity.kind = Activity::Kind::motion;
      activity.motion = definition["motion"];
      const humans::MotionClip* clip = humans::builtin_motion(activity.motion);
      if (!clip) {
        error(at + "/motion", "unknown motion '" + activity.motion + "'; the shipped ones are " + known_motions());
        activity.kind = Activity::Kind::wait;  // keeps the chain checks meaningful
      } else if (!definition.contains("duration")) {
        if (clip->loops()) error(at, "motion '" + activity.motion + "' loops: give a 'duration'");
        activity.min_duration = activity.max_duration = clip->duration();
      }
    } else if (definition.contains("walk")) {
      activity.kind = Activity::Kind::walk;
      const json& places = definition["walk"];
      for (std::size_t i = 0; i < places.size(); ++i) {
        const std::string place = places[i];
        if (!locations_.contains(place)) {
          error(at + "/walk/" + std::to_string(i), "unknown location '" + place + "'");
          continue;
        }
        activity.locations.push_back(locations_.at(place));
      }
    }
    if (definition.contains("turn")) {
      activity.kind = Activity::Kind::turn;
      const json& range = definition["turn"];
      activity.min_angle = range.is_array() ? range.at(0).get<double>() : range.get<double>();
      activity.max_angle = range.is_array() ? range.at(1).get<double>() : activity.min_angle;
      if (activity.max_angle < activity.min_angle) error(at + "/turn", "the largest angle is smaller than the smallest");
    }
    const char* key = definition.contains("wait") ? "wait" : "duration";
    if (definition.contains(key)) {
      const json& range = definition[key];
      activity.min_duration = range.is_array() ? range.at(0).get<double>() : range.get<double>();
      activity.max_duration = range.is_array() ? range.at(1).get<double>() : activity.min_duration;
      if (activity.max_duration < activity.min_duration) error(at + "/" + key, "the longest duration is shorter than the shortest");
    }
    return activity;
  }

  TransitionMatrix read_transitions(const ActivityModel& model, const json& rows, const std::string& at) {
    const std::size_t n = model.activities.size();
    TransitionMatrix matrix(n, std::vector<double>(n, 0.0));
    for (const auto& [from, row] : rows.items()) {
      const std::string row_at = at + "/" + core::pointer_token(from);
      if (!index_.contains(from)) {
        error(row_at, "'" + from + "' is not one of the model's activities");
        continue;
      }
      double sum = 0.0;
      for (const auto& [to, probability] : row.items()) {
        if (!index_.contains(to)) {
          error(row_at + "/" + core::pointer_token(to), "'" + to + "' is not one of the model's activities");
          continue;
        }
        matrix[index_.at(from)][index_.at(to)] = probability.get<double>();
        sum += probability.get<double>();
      }
      if (std::abs(sum - 1.0) > kRowSumTolerance) {
        error(row_at, "the probabilities after '" + from + "' add up to " + json(sum).dump() + ", not 1");
      }
    }
    for (const Activity& activity : model.activities) {
      if (!rows.contains(activity.name)) {
        error(at, "'" + activity.name + "' has no transitions: a person could never leave it");
      }
    }
    return matrix;
  }

  /// What a body can do next, and that no activity traps the person.
  void check_chain(const ActivityModel& model, const TransitionMatrix& matrix, const std::string& at) {
    const std::size_t n = model.activities.size();
    // The postures each activity can be begun in, from the start (standing), to a fixed point.
    std::vector<unsigned> entered(n, 0u);
    entered[model.start] = bit(Posture::standing);
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t a = 0; a < n; ++a) {
        if (!entered[a]) continue;
        const unsigned left = leaves(model.activities[a], entered[a]);
        for (std::size_t b = 0; b < n; ++b) {
          if (matrix[a][b] <= 0.0 || (entered[b] | left) == entered[b]) continue;
          entered[b] |= left;
          changed = true;
        }
      }
    }
    for (std::size_t a = 0; a < n; ++a) {
      if (!entered[a]) continue;
      const unsigned left = leaves(model.activities[a], entered[a]);
      for (std::size_t b = 0; b < n; ++b) {
        const std::optional<Posture> needed = needs(model.activities[b]);
        if (matrix[a][b] <= 0.0 || !needed || left == bit(*needed)) continue;
        for (const Posture posture : {Posture::standing, Posture::seated, Posture::lying}) {
          if (!(left & bit(posture)) || posture == *needed) continue;
          error(at + "/" + core::pointer_token(model.activities[a].name) + "/" + core::pointer_token(model.activities[b].name),
                "'" + model.activities[b].name + "' begins " + posture_name(*needed) + ", but '" + model.activities[a].name +
                    "' can leave the person " + posture_name(posture) + ": go through an activity that gets them " +
                    posture_name(*needed) + " first");
          break;
        }
      }
    }
    // Every activity reached must be left, and lead back to the start.
    std::vector<bool> returns(n, false);
    returns[model.start] = true;
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t a = 0; a < n; ++a) {
        if (returns[a]) continue;
        for (std::size_t b = 0; b < n && !returns[a]; ++b) returns[a] = matrix[a][b] > 0.0 && returns[b];
        changed |= returns[a];
      }
    }
    for (std::size_t a = 0; a < n; ++a) {
      if (!entered[a]) continue;
      const std::string& name = model.activities[a].name;
      if (matrix[a][a] >= 1.0) {
        error(at + "/" + core::pointer_token(name), "'" + name + "' cannot be left: it goes on to itself only");
      } else if (!returns[a]) {
        error(at + "/" + core::pointer_token(name), "'" + name + "' cannot be left for good: nothing after it leads back to '" +
                                                       model.activities[model.start].name + "', the start");
      }
    }
  }

  std::string pointer_;
  const std::map<std::string, int>& locations_;
  Errors& errors_;
  std::map<std::string, int> index_;
};

}  // namespace

Posture posture_at(const humans::MotionClip& clip, double time) {
  const double drop = -clip.sample(time).root.z();
  if (drop < kSeatedRootDrop) return Posture::standing;
  return drop < kLyingRootDrop ? Posture::seated : Posture::lying;
}

const TransitionMatrix& ActivityModel::transitions_for(const std::string& type) const {
  const auto own = transitions_by_type.find(type);
  return own == transitions_by_type.end() ? transitions : own->second;
}

std::vector<ActivityModel> read_activity_models(const json& models, const std::map<std::string, int>& locations, Errors& errors) {
  std::vector<ActivityModel> read;
  for (const auto& [name, entry] : models.items()) {
    read.push_back(ModelReader("/activity_models/" + core::pointer_token(name), locations, errors).read(name, entry));
  }
  return read;
}

}  // namespace hrisim::scenario
