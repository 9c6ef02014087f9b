#include "humans/behaviour.hpp"

#include <array>
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

}  // namespace hrisim::humans
