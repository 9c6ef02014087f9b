#include "humans/behaviour.hpp"

#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

namespace hrisim::humans {
namespace {

constexpr std::array<std::pair<BehaviourType, std::string_view>, 6> kNames{{{BehaviourType::regular, "regular"},
                                                                            {BehaviourType::impassive, "impassive"},
                                                                            {BehaviourType::surprised, "surprised"},
                                                                            {BehaviourType::scared, "scared"},
                                                                            {BehaviourType::curious, "curious"},
                                                                            {BehaviourType::threatening, "threatening"}}};

}  // namespace

std::string_view behaviour_name(BehaviourType type) {
  for (const auto& [known, name] : kNames) {
    if (known == type) return name;
  }
  return "regular";
}

std::optional<BehaviourType> behaviour_type(std::string_view name) {
  for (const auto& [type, known] : kNames) {
    if (known == name) return type;
  }
  return std::nullopt;
}

Behaviour default_behaviour(BehaviourType type) {
  Behaviour behaviour;
  behaviour.type = type;
  switch (type) {
    case BehaviourType::regular:
    case BehaviourType::impassive:
      break;  // no reaction: a robot is another person, or an obstacle
    case BehaviourType::surprised:
      behaviour.detection_distance = 4.0;
      behaviour.duration = 30.0;
      break;
    case BehaviourType::scared:
      behaviour.detection_distance = 3.0;
      behaviour.duration = 40.0;
      behaviour.speed = 0.6;
      behaviour.force_factor = 20.0;
      break;
    case BehaviourType::curious:
      behaviour.detection_distance = 10.0;
      behaviour.duration = 40.0;
      behaviour.distance = 1.5;
      break;
    case BehaviourType::threatening:
      behaviour.detection_distance = 4.0;
      behaviour.duration = 40.0;
      behaviour.speed = 2.0;
      behaviour.distance = 1.4;
      break;
  }
  return behaviour;
}

Behaviour read_behaviour(const nlohmann::json& entry) {
  const std::string name = entry.is_string() ? entry.get<std::string>() : entry.at("type").get<std::string>();
  Behaviour behaviour = default_behaviour(behaviour_type(name).value_or(BehaviourType::regular));  // the schema knows the names
  if (!entry.is_object()) return behaviour;
  behaviour.detection_distance = entry.value("detection_distance", behaviour.detection_distance);
  behaviour.duration = entry.value("duration", behaviour.duration);
  behaviour.once = entry.value("once", behaviour.once);
  behaviour.speed = entry.value("speed", behaviour.speed);
  behaviour.distance = entry.value("distance", behaviour.distance);
  behaviour.force_factor = entry.value("force_factor", behaviour.force_factor);
  return behaviour;
}

}  // namespace hrisim::humans
