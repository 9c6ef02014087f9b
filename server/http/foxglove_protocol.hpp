#pragma once
// The Foxglove WebSocket protocol's framing (subprotocols foxglove.sdk.v1 and foxglove.websocket.v1,
// the same messages): the server's JSON messages, its binary messages (little-endian, an opcode
// first) and the client's binary messages read with a clear error for each way they can be wrong.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace hrisim::http::foxglove {

/// The subprotocols accepted, the SDK's first (older clients offer only the second).
inline const std::vector<std::string> kSubprotocols = {"foxglove.sdk.v1", "foxglove.websocket.v1"};

/// A channel the server advertises: its messages in `json`, described by a JSON Schema.
struct Channel {
  std::uint32_t id = 0;
  std::string topic;
  std::string schema_name;
};

/// A service the server advertises: a JSON request and response, each with a JSON Schema.
struct Service {
  std::uint32_t id = 0;
  std::string name;
  std::string request_schema, response_schema;  ///< schema names
};

/// Status levels.
enum class Level { info = 0, warning = 1, error = 2 };

nlohmann::json server_info(const std::string& name, const std::vector<std::string>& capabilities, const nlohmann::json& metadata,
                           const std::string& session_id);
nlohmann::json advertise(const std::vector<Channel>& channels);
nlohmann::json advertise_services(const std::vector<Service>& services);
nlohmann::json status(Level level, const std::string& message);
nlohmann::json service_call_failure(std::uint32_t service, std::uint32_t call, const std::string& message);

/// Binary server messages: a subscription's message (opcode 1), the time (2), a service's answer (3).
std::string message_data(std::uint32_t subscription, std::uint64_t nanoseconds, std::string_view payload);
std::string time_message(std::uint64_t nanoseconds);
std::string service_call_response(std::uint32_t service, std::uint32_t call, std::string_view encoding, std::string_view payload);

/// Binary client messages: what it publishes on a channel it advertised (opcode 1), a service call (2).
struct ClientMessage {
  std::uint32_t channel = 0;
  std::string payload;
};
struct ServiceCall {
  std::uint32_t service = 0, call = 0;
  std::string encoding, payload;
};
inline constexpr std::uint8_t kClientMessageData = 1;
inline constexpr std::uint8_t kServiceCallRequest = 2;
/// The message's opcode, or core::Error(bad_request) for an empty message.
std::uint8_t opcode_of(std::string_view message);
/// Each throws core::Error(bad_request) saying what is missing when the bytes are too short.
ClientMessage read_client_message(std::string_view message);
ServiceCall read_service_call(std::string_view message);

}  // namespace hrisim::http::foxglove
