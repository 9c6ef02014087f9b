#pragma once
// The rosbridge v2 protocol's server messages (docs/rosbridge.md): status lines, service responses,
// and a topic's message as a publish op in JSON text, in CBOR (`compression: cbor`) or as CDR bytes
// inside CBOR (`cbor-raw`). Free of sockets and sessions: the rosbridge socket sends these.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "http/router.hpp"

namespace hrisim::http::rosbridge {

enum class Compression { none, cbor, cbor_raw };
/// A subscription's compression by its name in the protocol ("none", "cbor", "cbor-raw"); nullopt
/// for another.
std::optional<Compression> compression_named(const std::string& name);

/// The string `key` of a client's op or service request; core::Error(bad_request) "KEY must be a
/// string" when it is missing or not one.
std::string string_field(const nlohmann::json& message, const char* key);

/// {"op": "status", "level", "msg"}, with the id of the operation it answers when it had one.
nlohmann::json status(const std::string& level, const std::string& message, const nlohmann::json& id = nullptr);
/// {"op": "service_response", "service", "values", "result"}, with the call's id when it had one.
nlohmann::json service_response(const std::string& service, const nlohmann::json& values, bool result, const nlohmann::json& id = nullptr);

/// JSON text of a message; JSON binary in it (a uint8[] field) written as base64 text, as rosbridge
/// writes uint8[] in JSON.
std::string json_text(const nlohmann::json& message);

/// A message of `type` on `topic`, complete (its fields left out at their defaults, ros::conform), as
/// the subscription's compression wants it: JSON text; a binary
/// CBOR message; or a binary CBOR message whose msg is {secs, nsecs, bytes} with the message in CDR
/// and the simulated time it was sent at.
Response publish(const std::string& topic, const std::string& type, const nlohmann::json& message, Compression compression, double seconds);

}  // namespace hrisim::http::rosbridge
