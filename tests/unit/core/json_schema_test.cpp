#include "core/json_schema.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

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
  EXPECT_EQ(by_pointer["/pets/1/species"], "missing required key 'species'") << "at the pointer the key would have";
  EXPECT_EQ(by_pointer["/pets/2/species"], "expected string, got integer");
  EXPECT_NE(by_pointer["/colour"].find("unknown key 'colour'"), std::string::npos);
}

TEST(JsonSchema, MissingRequiredAndWrongRootType) {
  const auto missing = person_schema().validate(json::object());
  ASSERT_EQ(missing.size(), 2u);
  EXPECT_EQ(missing[0].pointer, "/name");
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
  EXPECT_THROW(JsonSchema(json::parse(R"({"type": "string", "format": "email"})")), Error) << "format would be an annotation only";
  EXPECT_THROW(JsonSchema(json::parse(R"({"properties": {"a": {"not": {"type": "string"}}}})")), Error);
  EXPECT_THROW(JsonSchema(json::parse(R"({"type": "string", "pattern": "(unclosed"})")), Error);
  EXPECT_THROW(JsonSchema(json::parse(R"({"items": {"$ref": "#/$defs/missing"}})")), Error);
}

TEST(JsonSchema, StringsCountCharactersAndMatchPatterns) {
  const JsonSchema tag(json::parse(R"({"type": "string", "maxLength": 3, "pattern": "^[^,\\s]+$"})"));
  EXPECT_TRUE(tag.validate("äöü").empty()) << "three characters, six bytes";
  const auto long_one = tag.validate("abcd");
  ASSERT_EQ(long_one.size(), 1u);
  EXPECT_EQ(long_one[0].message, "must have at most 3 characters (got 4)");
  const auto spaced = tag.validate("a b");
  ASSERT_EQ(spaced.size(), 1u);
  EXPECT_NE(spaced[0].message.find("must match the pattern"), std::string::npos);
}

TEST(JsonSchema, UniqueItemsAndObjectSizes) {
  const JsonSchema schema(json::parse(R"({"type": "object", "maxProperties": 2, "additionalProperties": {"type": "array", "uniqueItems": true}})"));
  EXPECT_TRUE(schema.validate(json::parse(R"({"a": [1, 2], "b": []})")).empty());
  const auto errors = schema.validate(json::parse(R"({"a": [1, 2, 1], "b": [], "c": []})"));
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_EQ(errors[0], (ValidationError{"", "must have at most 2 keys (got 3)"}));
  EXPECT_EQ(errors[1], (ValidationError{"/a/2", "repeats item 0: the items must be unique"}));
}

TEST(JsonSchema, FalseForbidsAKeyAndIfThenElseChooses) {
  // As a controller's schema: idle takes no goal, the others may have one.
  const JsonSchema schema(json::parse(R"({"type": "object", "properties": {"type": {"type": "string"}, "goal": {"type": "string"}},
    "if": {"properties": {"type": {"const": "idle"}}}, "then": {"description": "idle takes no goal", "properties": {"goal": false}}, "else": {"required": ["goal"]}})"));
  EXPECT_TRUE(schema.validate(json::parse(R"({"type": "idle"})")).empty());
  EXPECT_TRUE(schema.validate(json::parse(R"({"type": "goal", "goal": "exit"})")).empty());
  EXPECT_EQ(schema.validate(json::parse(R"({"type": "idle", "goal": "exit"})")), (std::vector<ValidationError>{{"/goal", "is not allowed here: idle takes no goal"}}));
  EXPECT_EQ(JsonSchema(json::parse(R"({"items": false})")).validate(json::parse("[1]")), (std::vector<ValidationError>{{"/0", "is not allowed here"}}));
  EXPECT_EQ(schema.validate(json::parse(R"({"type": "goal"})")), (std::vector<ValidationError>{{"/goal", "missing required key 'goal'"}}));
}

TEST(JsonSchema, AllOfReportsEveryPartsErrors) {
  const JsonSchema schema(json::parse(R"({"allOf": [{"required": ["a"]}, {"properties": {"b": {"type": "integer"}}}]})"));
  const auto errors = schema.validate(json::parse(R"({"b": 1.5})"));
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_EQ(errors[0], (ValidationError{"/a", "missing required key 'a'"}));
  EXPECT_EQ(errors[1].pointer, "/b");
}

TEST(JsonSchema, ASchemaInsideALargerDocumentFollowsItsReferences) {
  // As a request body in an OpenAPI description: its $refs point into the description.
  const auto description = std::make_shared<const json>(json::parse(R"({
    "paths": {"/step": {"post": {"schema": {"type": "object", "properties": {"n": {"$ref": "#/components/Count"}}}}}},
    "components": {"Count": {"type": "integer", "minimum": 1}, "Broken": {"not": {}}}})"));
  const JsonSchema step(description, "/paths/~1step/post/schema");
  const JsonSchema described_count(std::make_shared<const json>(json::parse(R"({"$defs": {"n": {"type": "integer"}},
    "properties": {"n": {"$ref": "#/$defs/n", "maximum": 9, "description": "a $ref's siblings apply too"}}})")), "");
  EXPECT_EQ(described_count.validate(json::parse(R"({"n": 10})")), (std::vector<ValidationError>{{"/n", "must be at most 9 (got 10)"}}));
  EXPECT_TRUE(step.validate(json::parse(R"({"n": 3})")).empty());
  EXPECT_EQ(step.validate(json::parse(R"({"n": 0})")), (std::vector<ValidationError>{{"/n", "must be at least 1 (got 0)"}}));
  EXPECT_THROW(JsonSchema(description, "/components/Broken"), Error) << "keywords are checked where the schema is";
  EXPECT_THROW(JsonSchema(description, "/paths/~1none"), Error);
}

}  // namespace
}  // namespace hrisim::core
