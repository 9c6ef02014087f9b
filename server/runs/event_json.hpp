#pragma once
// Events as JSON, outside the simulation: the edge where a typed event (sim/event_types.hpp) becomes
// the shape the API, the store and the browser show, {"tick", "time", "kind", "subject", "data"}.
#include <nlohmann/json.hpp>

#include "sim/event_types.hpp"

namespace hrisim::runs {

/// The event's `data` object: its kind's fields by name.
nlohmann::json event_data_json(const sim::EventData& data);
nlohmann::json event_json(const sim::Event& event);

}  // namespace hrisim::runs
