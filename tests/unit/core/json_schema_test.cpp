#include "core/json_schema.hpp"

#include <gtest/gtest.h>

#include <map>

#include "core/error.hpp"

namespace hrisim::core {
namespace {

using nlohmann::json;

const JsonSchema& person_schema() {
  static const JsonSchema schema(json::parse(R"({
    "type": "object", "required": ["name", "age"], "additionalProperties": false,
    "properties": {
      "name": {"type": "string", "minLength": 1},
      "age": {"type": "integer", "minimum": 0, "maximum": 150},
      "speed": {"type": "number", "exclusiveMinimum": 0},
      "kind": {"enum": ["adult", "child"]},
      "pets": {"type": "array", "maxItems": 2, "items": {"$ref": "#/$defs/pet"}},
      "goal": {"oneOf": [
        {"type": "object", "required": ["location"], "additionalProperties": false, "properties": {"location": {"type": "string"}}},
        {"type": "object", "required": ["x", "y"], "additionalProperties": false, "properties": {"x": {"type": "number"}, "y": {"type": "number"}}}
      ]}
    },
    "$defs": {"pet": {"type": "object", "required": ["species"], "properties": {"species": {"type": "string"}}}}
  })"));
  return schema;
}

TEST(JsonSchema, ValidDocumentHasNoErrors) {
  EXPECT_TRUE(person_schema().validate(json::parse(R"({"name": "ana", "age": 30, "goal": {"x": 1, "y": 2}})")).empty());
  EXPECT_TRUE(person_schema().validate(json::parse(R"({"name": "ana", "age": 30.0})")).empty()) << "30.0 is an integer";
}

TEST(JsonSchema, EveryErrorWithItsPointer) {
  const auto errors = person_schema().validate(json::parse(
      R"({"name": "", "age": 200, "speed": 0, "kind": "robot", "pets": [{"species": "cat"}, {}, {"species": 3}], "colour": "red"})"));
  std::map<std::string, std::string> by_pointer;
  for (const auto& e : errors) by_pointer[e.pointer] = e.message;
  EXPECT_EQ(errors.size(), 8u);
  EXPECT_EQ(by_pointer["/name"], "must not be empty");
  EXPECT_EQ(by_pointer["/age"], "must be at most 150 (got 200)");
  EXPECT_EQ(by_pointer["/speed"], "must be greater than 0 (got 0)");
  EXPECT_EQ(by_pointer["/kind"], "must be one of: adult, child (got \"robot\")");
  EXPECT_EQ(by_pointer["/pets"], "must have at most 2 items (got 3)");
  EXPECT_EQ(by_pointer["/pets/1"], "missing required key 'species'");
  EXPECT_EQ(by_pointer["/pets/2/species"], "expected string, got integer");
  EXPECT_NE(by_pointer["/colour"].find("unknown key 'colour'"), std::string::npos);
}

TEST(JsonSchema, MissingRequiredAndWrongRootType) {
  const auto missing = person_schema().validate(json::object());
  ASSERT_EQ(missing.size(), 2u);
  EXPECT_EQ(missing[0].pointer, "");
  EXPECT_EQ(missing[0].message, "missing required key 'name'");
  const auto wrong = person_schema().validate(json::array());
  ASSERT_EQ(wrong.size(), 1u);
  EXPECT_EQ(wrong[0].message, "expected object, got array");
}

TEST(JsonSchema, OneOfReportsTheIntendedAlternative) {
  const auto typo = person_schema().validate(json::parse(R"({"name": "a", "age": 1, "goal": {"x": 1, "y": "up"}})"));
  ASSERT_EQ(typo.size(), 1u);
  EXPECT_EQ(typo[0].pointer, "/goal/y");
  const auto neither = person_schema().validate(json::parse(R"({"name": "a", "age": 1, "goal": {"z": 1}})"));
  ASSERT_EQ(neither.size(), 1u);
  EXPECT_EQ(neither[0].pointer, "/goal");
  EXPECT_EQ(neither[0].message, "expected one of the forms: location | x, y");
}

TEST(JsonSchema, PointerTokensAreEscaped) {
  const JsonSchema schema(json::parse(R"({"type": "object", "additionalProperties": {"type": "number"}})"));
  const auto errors = schema.validate(json::parse(R"({"a/b~c": "x"})"));
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].pointer, "/a~1b~0c");
}

TEST(JsonSchema, UnsupportedKeywordIsRefusedUpFront) {
  EXPECT_THROW(JsonSchema(json::parse(R"({"type": "string", "pattern": "^a"})")), Error);
  EXPECT_THROW(JsonSchema(json::parse(R"({"properties": {"a": {"format": "email"}}})")), Error);
}

}  // namespace
}  // namespace hrisim::core
