#pragma once
// Validation of JSON documents against the JSON Schema subset hrisim's own schemas use
// (api/*.schema.json): type, properties, required, additionalProperties, items, enum, const,
// minimum/maximum (and exclusive), minItems/maxItems, minLength, $ref to "#/$defs/...", oneOf, anyOf.
// Every error is reported, each with the JSON pointer of the offending value.
#include <nlohmann/json.hpp>
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

  /// All errors of the document, in document order; empty when it is valid.
  std::vector<ValidationError> validate(const nlohmann::json& document) const;

 private:
  void check(const nlohmann::json& schema, const nlohmann::json& value, const std::string& pointer,
             std::vector<ValidationError>& errors) const;
  const nlohmann::json& resolve(const nlohmann::json& schema) const;

  nlohmann::json schema_;
};

/// Escapes a key for use in a JSON pointer ("~" → "~0", "/" → "~1").
std::string pointer_token(const std::string& key);

/// 1-based line and column of byte `offset` in `text` (for syntax errors people can find).
std::pair<std::size_t, std::size_t> line_and_column(std::string_view text, std::size_t offset);

/// "object", "array", "string", "number", "integer", "boolean" or "null".
std::string json_type_name(const nlohmann::json& value);

}  // namespace hrisim::core
