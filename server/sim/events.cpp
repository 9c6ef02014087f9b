#include "sim/events.hpp"

#include "core/state_hash.hpp"
#include "sim/event_json.hpp"

namespace hrisim::sim {

void emit(const scenario::Model& model, State& state, std::string subject, EventData data) {
  core::StateHasher digest;
  digest.add(state.events_digest).add(state.tick).add(std::visit([](const auto& what) { return std::remove_cvref_t<decltype(what)>::kind; }, data));
  digest.add(std::string_view(subject)).add(std::string_view(event_data_json(data).dump()));
  state.events_digest = digest.value();
  state.events.push_back({state.tick, time_of(model, state), std::move(subject), std::move(data)});
}

}  // namespace hrisim::sim
