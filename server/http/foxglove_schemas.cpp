// The JSON Schemas hrisim advertises its Foxglove channels and services with: each describes the
// fields hrisim sends (Foxglove's panels know the well-known messages by schema name; the schema tells
// it the types, and which strings are base64 bytes).
#include <map>

#include "core/error.hpp"
#include "core/text.hpp"
#include "http/foxglove_messages.hpp"

namespace hrisim::http::foxglove {
namespace {

using nlohmann::json;

json of_type(const char* type) { return {{"type", type}}; }
json object(std::initializer_list<std::pair<const char*, json>> properties) {
  json schema = {{"type", "object"}, {"properties", json::object()}};
  for (const auto& [name, property] : properties) schema["properties"][name] = property;
  return schema;
}
json list_of(json items) { return {{"type", "array"}, {"items", std::move(items)}}; }
json titled(json schema, const std::string& title) {
  schema["title"] = title;
  return schema;
}

json time_schema() { return titled(object({{"sec", of_type("integer")}, {"nsec", of_type("integer")}}), "time"); }
json vector3() { return object({{"x", of_type("number")}, {"y", of_type("number")}, {"z", of_type("number")}}); }
json quaternion() { return object({{"x", of_type("number")}, {"y", of_type("number")}, {"z", of_type("number")}, {"w", of_type("number")}}); }
json pose() { return object({{"position", vector3()}, {"orientation", quaternion()}}); }
json colour() { return object({{"r", of_type("number")}, {"g", of_type("number")}, {"b", of_type("number")}, {"a", of_type("number")}}); }
json bytes() { return {{"type", "string"}, {"contentEncoding", "base64"}}; }

json scene_update() {
  const json solid = object({{"pose", pose()}, {"size", vector3()}, {"color", colour()}});
  json cylinder = solid;
  cylinder["properties"]["bottom_scale"] = of_type("number");
  cylinder["properties"]["top_scale"] = of_type("number");
  const json line = object({{"type", of_type("integer")}, {"pose", pose()}, {"thickness", of_type("number")}, {"scale_invariant", of_type("boolean")},
                            {"points", list_of(vector3())}, {"color", colour()}, {"colors", list_of(colour())}, {"indices", list_of(of_type("integer"))}});
  const json entity = object({{"timestamp", time_schema()}, {"frame_id", of_type("string")}, {"id", of_type("string")},
                              {"lifetime", titled(object({{"sec", of_type("integer")}, {"nsec", of_type("integer")}}), "duration")},
                              {"frame_locked", of_type("boolean")}, {"metadata", list_of(object({{"key", of_type("string")}, {"value", of_type("string")}}))},
                              {"arrows", list_of(of_type("object"))}, {"cubes", list_of(solid)}, {"spheres", list_of(solid)},
                              {"cylinders", list_of(cylinder)}, {"lines", list_of(line)}, {"triangles", list_of(of_type("object"))},
                              {"texts", list_of(of_type("object"))}, {"models", list_of(of_type("object"))}});
  return object({{"deletions", list_of(object({{"timestamp", time_schema()}, {"type", of_type("integer")}, {"id", of_type("string")}}))},
                 {"entities", list_of(entity)}});
}

json frame_transforms() {
  return object({{"transforms", list_of(object({{"timestamp", time_schema()}, {"parent_frame_id", of_type("string")}, {"child_frame_id", of_type("string")},
                                                 {"translation", vector3()}, {"rotation", quaternion()}}))}});
}

json laser_scan() {
  return object({{"timestamp", time_schema()}, {"frame_id", of_type("string")}, {"pose", pose()}, {"start_angle", of_type("number")},
                 {"end_angle", of_type("number")}, {"ranges", list_of(of_type("number"))}, {"intensities", list_of(of_type("number"))}});
}

json metrics() {
  return object({{"tick", of_type("integer")}, {"time", of_type("number")},
                 {"metrics", {{"type", "object"}, {"additionalProperties", {{"type", json::array({"number", "null"})}}}}}});
}

/// Every schema by name, written once as JSON text.
std::map<std::string, std::string> all_schemas() {
  std::map<std::string, json> schemas = {
      {"foxglove.SceneUpdate", scene_update()},
      {"foxglove.FrameTransforms", frame_transforms()},
      {"foxglove.LaserScan", laser_scan()},
      {"foxglove.PosesInFrame", object({{"timestamp", time_schema()}, {"frame_id", of_type("string")}, {"poses", list_of(pose())}})},
      {"foxglove.CompressedImage", object({{"timestamp", time_schema()}, {"frame_id", of_type("string")}, {"data", bytes()}, {"format", of_type("string")}})},
      {"foxglove.RawImage", object({{"timestamp", time_schema()}, {"frame_id", of_type("string")}, {"width", of_type("integer")}, {"height", of_type("integer")},
                                    {"encoding", of_type("string")}, {"step", of_type("integer")}, {"data", bytes()}})},
      {"foxglove.Log", object({{"timestamp", time_schema()}, {"level", of_type("integer")}, {"message", of_type("string")}, {"name", of_type("string")},
                               {"file", of_type("string")}, {"line", of_type("integer")}})},
      {"hrisim.Metrics", metrics()},
      {"hrisim.StepRequest", object({{"n", of_type("integer")}})},
      {"hrisim.ResetRequest", object({{"seed", of_type("integer")}})},
      {"hrisim.SeekRequest", object({{"tick", of_type("integer")}})},
      {"hrisim.Status", object({{"tick", of_type("integer")}, {"time", of_type("number")}, {"finished", of_type("boolean")}})},
  };
  std::map<std::string, std::string> texts;
  for (auto& [name, schema] : schemas) {
    schema = titled(std::move(schema), name);
    texts[name] = core::json_text(schema);
  }
  return texts;
}

}  // namespace

const std::string& schema_text(const std::string& schema_name) {
  static const std::map<std::string, std::string> schemas = all_schemas();
  const auto found = schemas.find(schema_name);
  if (found == schemas.end()) throw core::Error(core::ErrorCode::internal, "no JSON Schema for " + schema_name);
  return found->second;
}

}  // namespace hrisim::http::foxglove
