#include "http/foxglove_protocol.hpp"

#include <bit>
#include <cstring>

#include "core/error.hpp"
#include "http/foxglove_messages.hpp"

namespace hrisim::http::foxglove {
namespace {

using nlohmann::json;

static_assert(std::endian::native == std::endian::little, "Foxglove's binary messages are written in the host's byte order");

template <typename Integer>
void append(std::string& out, Integer value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

/// Reads a little-endian integer at `at` and moves past it; `what` names it when the bytes end first.
template <typename Integer>
Integer take(std::string_view message, std::size_t& at, const char* what) {
  if (message.size() < at + sizeof(Integer)) {
    throw core::Error(core::ErrorCode::bad_request, std::string("binary message too short: no ") + what + " at byte " + std::to_string(at),
                      {{"bytes", message.size()}});
  }
  Integer value;
  std::memcpy(&value, message.data() + at, sizeof value);
  at += sizeof value;
  return value;
}

json schema_described(const std::string& schema_name) {
  return {{"encoding", "json"}, {"schemaName", schema_name}, {"schemaEncoding", "jsonschema"}, {"schema", schema_text(schema_name)}};
}

}  // namespace

json server_info(const std::string& name, const std::vector<std::string>& capabilities, const json& metadata, const std::string& session_id) {
  return {{"op", "serverInfo"}, {"name", name}, {"capabilities", capabilities}, {"supportedEncodings", {"json"}}, {"metadata", metadata},
          {"sessionId", session_id}};
}

json advertise(const std::vector<Channel>& channels) {
  json listed = json::array();
  for (const Channel& channel : channels) {
    json described = schema_described(channel.schema_name);
    described["id"] = channel.id;
    described["topic"] = channel.topic;
    listed.push_back(std::move(described));
  }
  return {{"op", "advertise"}, {"channels", std::move(listed)}};
}

json advertise_services(const std::vector<Service>& services) {
  json listed = json::array();
  for (const Service& service : services) {
    // The request and response described twice: as the protocol describes them now, and in the older
    // requestSchema/responseSchema that clients before it read.
    listed.push_back({{"id", service.id}, {"name", service.name}, {"type", service.name},
                      {"request", schema_described(service.request_schema)}, {"response", schema_described(service.response_schema)},
                      {"requestSchema", schema_text(service.request_schema)}, {"responseSchema", schema_text(service.response_schema)}});
  }
  return {{"op", "advertiseServices"}, {"services", std::move(listed)}};
}

json status(Level level, const std::string& message) { return {{"op", "status"}, {"level", static_cast<int>(level)}, {"message", message}}; }

json service_call_failure(std::uint32_t service, std::uint32_t call, const std::string& message) {
  return {{"op", "serviceCallFailure"}, {"serviceId", service}, {"callId", call}, {"message", message}};
}

std::string message_data(std::uint32_t subscription, std::uint64_t nanoseconds, std::string_view payload) {
  std::string out;
  out.reserve(13 + payload.size());
  append(out, std::uint8_t{1});
  append(out, subscription);
  append(out, nanoseconds);
  out.append(payload);
  return out;
}

std::string time_message(std::uint64_t nanoseconds) {
  std::string out;
  append(out, std::uint8_t{2});
  append(out, nanoseconds);
  return out;
}

std::string service_call_response(std::uint32_t service, std::uint32_t call, std::string_view encoding, std::string_view payload) {
  std::string out;
  append(out, std::uint8_t{3});
  append(out, service);
  append(out, call);
  append(out, static_cast<std::uint32_t>(encoding.size()));
  out.append(encoding);
  out.append(payload);
  return out;
}

std::uint8_t opcode_of(std::string_view message) {
  if (message.empty()) throw core::Error(core::ErrorCode::bad_request, "empty binary message: no opcode");
  return static_cast<std::uint8_t>(message[0]);
}

ClientMessage read_client_message(std::string_view message) {
  std::size_t at = 1;
  ClientMessage read;
  read.channel = take<std::uint32_t>(message, at, "channel id");
  read.payload = std::string(message.substr(at));
  return read;
}

ServiceCall read_service_call(std::string_view message) {
  std::size_t at = 1;
  ServiceCall read;
  read.service = take<std::uint32_t>(message, at, "service id");
  read.call = take<std::uint32_t>(message, at, "call id");
  const std::uint32_t length = take<std::uint32_t>(message, at, "encoding length");
  if (message.size() - at < length) {
    throw core::Error(core::ErrorCode::bad_request, "binary message too short: its encoding's " + std::to_string(length) + " bytes are not all there");
  }
  read.encoding = std::string(message.substr(at, length));
  read.payload = std::string(message.substr(at + length));
  return read;
}

}  // namespace hrisim::http::foxglove
