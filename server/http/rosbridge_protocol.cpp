#include "http/rosbridge_protocol.hpp"

#include "core/error.hpp"
#include "core/text.hpp"
#include "http/ros_messages.hpp"
#include "http/ros_topics.hpp"

namespace hrisim::http::rosbridge {
namespace {

using nlohmann::json;

/// The value with every JSON binary in it as base64 text.
json with_base64(const json& value) {
  if (value.is_binary()) return core::base64_encode(std::string(value.get_binary().begin(), value.get_binary().end()));
  if (!value.is_structured()) return value;
  json copy = value;
  for (auto& item : copy) item = with_base64(item);
  return copy;
}

Response binary(const std::vector<std::uint8_t>& bytes) { return Response{200, kBinaryContentType, std::string(bytes.begin(), bytes.end()), {}, {}}; }

}  // namespace

std::optional<Compression> compression_named(const std::string& name) {
  if (name == "none") return Compression::none;
  if (name == "cbor") return Compression::cbor;
  if (name == "cbor-raw") return Compression::cbor_raw;
  return std::nullopt;
}

std::string string_field(const json& message, const char* key) {
  if (!message.contains(key) || !message[key].is_string()) throw core::Error(core::ErrorCode::bad_request, std::string(key) + " must be a string");
  return message[key].get<std::string>();
}

json status(const std::string& level, const std::string& message, const json& id) {
  json status = {{"op", "status"}, {"level", level}, {"msg", message}};
  if (!id.is_null()) status["id"] = id;
  return status;
}

json service_response(const std::string& service, const json& values, bool result, const json& id) {
  json response = {{"op", "service_response"}, {"service", service}, {"values", values}, {"result", result}};
  if (!id.is_null()) response["id"] = id;
  return response;
}

std::string json_text(const json& message) { return core::json_text(with_base64(message)); }

Response publish(const std::string& topic, const std::string& type, const json& message, Compression compression, double seconds) {
  switch (compression) {
    case Compression::none:
      return Response{200, "application/json", json_text({{"op", "publish"}, {"topic", topic}, {"msg", ros::conform(type, message)}}), {}, {}};
    case Compression::cbor:
      return binary(json::to_cbor({{"op", "publish"}, {"topic", topic}, {"msg", ros::conform(type, message)}}));
    case Compression::cbor_raw: {
      const std::string cdr = ros::encode_cdr(type, message);
      const json time = ros::time_of(seconds);
      const json raw = {{"secs", time["sec"]}, {"nsecs", time["nanosec"]}, {"bytes", json::binary(std::vector<std::uint8_t>(cdr.begin(), cdr.end()))}};
      return binary(json::to_cbor({{"op", "publish"}, {"topic", topic}, {"msg", raw}}));
    }
  }
  return Response::nothing();
}

}  // namespace hrisim::http::rosbridge
