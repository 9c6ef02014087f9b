#pragma once
// Validation of JSON documents against the JSON Schema (2020-12) subset hrisim's own schemas use
// (api/*.schema.json, and the request bodies and messages of api/openapi.yaml and api/asyncapi.yaml):
// type, properties, required, additionalProperties, items, enum, const, minimum/maximum (and
// exclusive), minItems/maxItems, uniqueItems, minLength/maxLength, pattern, minProperties/
// maxProperties, $ref to any "#/..." pointer of the document, oneOf, anyOf, allOf, if/then/else, and
// the boolean schemas true and false. Every error is reported, each with the JSON pointer of the
// offending value.
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hrisim::core {

struct ValidationError {
  std::string pointer;  ///< RFC 6901 JSON pointer into the document, "" for the root
  std::string message;
  bool operator==(const ValidationError&) const = default;
};

class JsonSchema {
 public:
  /// Throws core::Error(internal) when the schema uses a keyword outside the supported subset, so a
  /// schema never silently checks less than it says.
  explicit JsonSchema(nlohmann::json schema);

  /// The schema at `pointer` (RFC 6901) within a larger document that holds it, such as an OpenAPI
  /// description; its $refs point into that document. Keywords are checked as above, for the schema
  /// and for every schema it refers to.
  JsonSchema(std::shared_ptr<const nlohmann::json> document, const std::string& pointer);

  /// All errors of the document, in document order; empty when it is valid.
  std::vector<ValidationError> validate(const nlohmann::json& document) const;

 private:
  struct Compiled;
  void check(const nlohmann::json& schema, const nlohmann::json& value, const std::string& pointer,
             std::vector<ValidationError>& errors) const;
  const nlohmann::json& resolve(const nlohmann::json& schema) const;
  void check_keywords(const nlohmann::json& schema, const std::string& where);

  std::shared_ptr<const nlohmann::json> document_;
  const nlohmann::json* schema_;
  /// Compiled once when the schema is read: every $ref's target and every pattern.
  std::shared_ptr<Compiled> compiled_;
};

/// Escapes a key for use in a JSON pointer ("~" → "~0", "/" → "~1").
std::string pointer_token(const std::string& key);

/// 1-based line and column of byte `offset` in `text` (for syntax errors people can find).
std::pair<std::size_t, std::size_t> line_and_column(std::string_view text, std::size_t offset);

/// "object", "array", "string", "number", "integer", "boolean" or "null".
std::string json_type_name(const nlohmann::json& value);

}  // namespace hrisim::core
