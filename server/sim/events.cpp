#include "sim/events.hpp"

#include <type_traits>

#include "core/state_hash.hpp"

namespace hrisim::sim {
namespace {

/// Folds each field an event lists, by name and value, into the events digest.
struct DigestFields {
  core::StateHasher& digest;
  template <class Value>
  void operator()(std::string_view name, const Value& value) const {
    digest.add(name);
    if constexpr (std::is_same_v<Value, std::optional<std::string>>) {
      digest.add(value.has_value());
      if (value) digest.add(std::string_view(*value));
    } else if constexpr (std::is_same_v<Value, events::NullWhenEmpty>) {
      digest.add(value.value.has_value());
      if (value.value) digest.add(std::string_view(*value.value));
    } else if constexpr (std::is_convertible_v<const Value&, std::string_view>) {
      digest.add(std::string_view(value));
    } else if constexpr (std::is_same_v<Value, bool> || std::is_same_v<Value, double>) {
      digest.add(value);
    } else {
      static_assert(std::is_integral_v<Value>, "an event's field is text, a number or a flag");
      digest.add(static_cast<std::int64_t>(value));
    }
  }
};

}  // namespace

void emit(const scenario::Model& model, State& state, std::string subject, EventData data) {
  core::StateHasher digest;
  digest.add(state.events_digest).add(state.tick).add(std::string_view(subject));
  std::visit(
      [&digest](const auto& what) {
        digest.add(std::remove_cvref_t<decltype(what)>::kind);
        what.visit_fields(DigestFields{digest});
      },
      data);
  state.events_digest = digest.value();
  state.events.push_back({state.tick, time_of(model, state), std::move(subject), std::move(data)});
}

}  // namespace hrisim::sim
