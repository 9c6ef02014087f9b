#pragma once
// The ROS 2 message types the rosbridge socket speaks (docs/rosbridge.md), as their .msg definitions:
// type names in both spellings, the definition text with its dependencies (rosapi's
// typedefs_full_text, which clients decode cbor-raw messages with), a JSON message checked against
// its type with the fields it leaves out filled in, and the message in CDR (what cbor-raw carries).
// hrisim's own code, no ROS: the definitions are written here, field by field.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace hrisim::http::ros {

/// A type name as ROS 2 spells it, "pkg/msg/Type", from "pkg/Type" or "pkg/msg/Type"; empty when it
/// is neither.
std::string canonical_type(const std::string& name);
/// Whether `name` (in either spelling) is a message type defined here.
bool known_type(const std::string& name);

/// The type's definition and those of every message type it uses, each after a line of '=' and
/// "MSG: pkg/Type", as rosapi's topics_and_raw_types gives them. Throws core::Error(internal) for a
/// type not defined here.
std::string full_definition(const std::string& type);

/// `message` as a complete message of `type`: every field there, those left out at their default
/// (0, false, "", empty, a message's own defaults). A field of the wrong kind, a fixed-size array of
/// another size, an unknown field: core::Error(bad_request) naming the field's path (e.g.
/// "linear.x must be a number").
nlohmann::json conform(const std::string& type, const nlohmann::json& message);

/// The message in CDR as ROS 2 sends it: the encapsulation header of little-endian plain CDR (00 01 00
/// 00), then the fields in order, each aligned to its size from the end of the header. uint8[] fields
/// may be held as JSON binary. Fields left out are written at their default (conform).
std::string encode_cdr(const std::string& type, const nlohmann::json& message);

}  // namespace hrisim::http::ros
