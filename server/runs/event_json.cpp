#include "runs/event_json.hpp"

namespace hrisim::runs {
namespace {

/// Puts each field the event lists into a JSON object.
struct JsonFields {
  nlohmann::json& object;
  template <class Value>
  void operator()(std::string_view name, const Value& value) const {
    object[std::string(name)] = value;
  }
  void operator()(std::string_view name, const std::optional<std::string>& value) const {
    if (value) object[std::string(name)] = *value;
  }
  void operator()(std::string_view name, sim::events::NullWhenEmpty field) const {
    object[std::string(name)] = field.value ? nlohmann::json(*field.value) : nlohmann::json();
  }
};

}  // namespace

nlohmann::json event_data_json(const sim::EventData& data) {
  nlohmann::json object = nlohmann::json::object();
  std::visit([&object](const auto& what) { what.visit_fields(JsonFields{object}); }, data);
  return object;
}

nlohmann::json event_json(const sim::Event& event) {
  return {{"tick", event.tick}, {"time", event.time}, {"kind", event.kind()}, {"subject", event.subject}, {"data", event_data_json(event.data)}};
}

}  // namespace hrisim::runs
