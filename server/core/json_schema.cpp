#include "core/json_schema.hpp"

#include <cmath>
#include <optional>
#include <set>

#include "core/error.hpp"

namespace hrisim::core {
namespace {

const std::set<std::string> kSupportedKeywords = {
    "$schema", "$id", "$defs", "$ref", "$comment", "title", "description", "default", "examples", "type",
    "properties", "required", "additionalProperties", "items", "enum", "const", "minimum", "maximum",
    "exclusiveMinimum", "exclusiveMaximum", "minItems", "maxItems", "minLength", "oneOf", "anyOf", "x-unit"};

void check_keywords(const nlohmann::json& schema, const std::string& where) {
  if (!schema.is_object()) return;
  for (const auto& [key, value] : schema.items()) {
    if (!kSupportedKeywords.contains(key)) {
      throw Error(ErrorCode::internal, "schema keyword '" + key + "' at " + where + " is not supported");
    }
    if (key == "properties" || key == "$defs") {
      for (const auto& [name, sub] : value.items()) check_keywords(sub, where + "/" + key + "/" + name);
    } else if (key == "items" || key == "additionalProperties") {
      check_keywords(value, where + "/" + key);
    } else if (key == "oneOf" || key == "anyOf") {
      for (std::size_t i = 0; i < value.size(); ++i) check_keywords(value[i], where + "/" + key + "/" + std::to_string(i));
    }
  }
}

bool type_matches(const std::string& type, const nlohmann::json& value) {
  if (type == "number") return value.is_number();
  if (type == "integer") {
    return value.is_number_integer() || (value.is_number_float() && std::trunc(value.get<double>()) == value.get<double>());
  }
  return json_type_name(value) == type;
}

std::string join(const nlohmann::json& names) {
  std::string text;
  for (const auto& name : names) text += (text.empty() ? "" : ", ") + (name.is_string() ? name.get<std::string>() : name.dump());
  return text;
}

}  // namespace

std::string pointer_token(const std::string& key) {
  std::string token;
  for (char c : key) {
    if (c == '~') {
      token += "~0";
    } else if (c == '/') {
      token += "~1";
    } else {
      token += c;
    }
  }
  return token;
}

std::string json_type_name(const nlohmann::json& value) {
  switch (value.type()) {
    case nlohmann::json::value_t::object: return "object";
    case nlohmann::json::value_t::array: return "array";
    case nlohmann::json::value_t::string: return "string";
    case nlohmann::json::value_t::boolean: return "boolean";
    case nlohmann::json::value_t::null: return "null";
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned: return "integer";
    default: return "number";
  }
}

JsonSchema::JsonSchema(nlohmann::json schema) : schema_(std::move(schema)) { check_keywords(schema_, "#"); }

std::vector<ValidationError> JsonSchema::validate(const nlohmann::json& document) const {
  std::vector<ValidationError> errors;
  check(schema_, document, "", errors);
  return errors;
}

const nlohmann::json& JsonSchema::resolve(const nlohmann::json& schema) const {
  const nlohmann::json* current = &schema;
  for (int depth = 0; current->is_object() && current->contains("$ref"); ++depth) {
    const std::string ref = (*current)["$ref"];
    if (depth > 32 || !ref.starts_with("#/")) throw Error(ErrorCode::internal, "unsupported schema reference " + ref);
    current = &schema_.at(nlohmann::json::json_pointer(ref.substr(1)));
  }
  return *current;
}

void JsonSchema::check(const nlohmann::json& schema_in, const nlohmann::json& value, const std::string& pointer,
                       std::vector<ValidationError>& errors) const {
  const nlohmann::json& schema = resolve(schema_in);
  if (!schema.is_object()) return;
  auto fail = [&](const std::string& message) { errors.push_back({pointer, message}); };

  if (const auto type = schema.find("type"); type != schema.end()) {
    const nlohmann::json types = type->is_array() ? *type : nlohmann::json::array({*type});
    bool matched = false;
    for (const auto& t : types) matched |= type_matches(t.get<std::string>(), value);
    if (!matched) {
      return fail("expected " + join(types) + ", got " + json_type_name(value));  // further checks would only repeat it
    }
  }
  if (const auto options = schema.find("enum"); options != schema.end()) {
    if (std::find(options->begin(), options->end(), value) == options->end()) {
      fail("must be one of: " + join(*options) + " (got " + value.dump() + ")");
    }
  }
  if (const auto constant = schema.find("const"); constant != schema.end() && *constant != value) {
    fail("must be " + constant->dump());
  }
  if (value.is_number()) {
    const double number = value.get<double>();
    if (!std::isfinite(number)) fail("must be a finite number");
    if (schema.contains("minimum") && number < schema["minimum"].get<double>()) {
      fail("must be at least " + schema["minimum"].dump() + " (got " + value.dump() + ")");
    }
    if (schema.contains("maximum") && number > schema["maximum"].get<double>()) {
      fail("must be at most " + schema["maximum"].dump() + " (got " + value.dump() + ")");
    }
    if (schema.contains("exclusiveMinimum") && number <= schema["exclusiveMinimum"].get<double>()) {
      fail("must be greater than " + schema["exclusiveMinimum"].dump() + " (got " + value.dump() + ")");
    }
    if (schema.contains("exclusiveMaximum") && number >= schema["exclusiveMaximum"].get<double>()) {
      fail("must be less than " + schema["exclusiveMaximum"].dump() + " (got " + value.dump() + ")");
    }
  }
  if (value.is_string() && schema.contains("minLength") &&
      value.get<std::string>().size() < schema["minLength"].get<std::size_t>()) {
    fail(schema["minLength"].get<std::size_t>() == 1 ? "must not be empty"
                                                     : "must have at least " + schema["minLength"].dump() + " characters");
  }
  if (value.is_array()) {
    if (schema.contains("minItems") && value.size() < schema["minItems"].get<std::size_t>()) {
      fail("must have at least " + schema["minItems"].dump() + " items (got " + std::to_string(value.size()) + ")");
    }
    if (schema.contains("maxItems") && value.size() > schema["maxItems"].get<std::size_t>()) {
      fail("must have at most " + schema["maxItems"].dump() + " items (got " + std::to_string(value.size()) + ")");
    }
    if (const auto items = schema.find("items"); items != schema.end()) {
      for (std::size_t i = 0; i < value.size(); ++i) check(*items, value[i], pointer + "/" + std::to_string(i), errors);
    }
  }
  if (value.is_object()) {
    if (const auto required = schema.find("required"); required != schema.end()) {
      for (const auto& name : *required) {
        if (!value.contains(name.get<std::string>())) fail("missing required key '" + name.get<std::string>() + "'");
      }
    }
    const auto properties = schema.find("properties");
    const auto additional = schema.find("additionalProperties");
    for (const auto& [key, member] : value.items()) {
      const std::string member_pointer = pointer + "/" + pointer_token(key);
      if (properties != schema.end() && properties->contains(key)) {
        check((*properties)[key], member, member_pointer, errors);
      } else if (additional != schema.end()) {
        if (additional->is_boolean()) {
          if (!additional->get<bool>()) {
            std::string known = properties != schema.end() ? "; known keys: " : "";
            if (properties != schema.end()) {
              for (const auto& [name, unused] : properties->items()) known += name + " ";
              known.pop_back();
            }
            errors.push_back({member_pointer, "unknown key '" + key + "'" + known});
          }
        } else {
          check(*additional, member, member_pointer, errors);
        }
      }
    }
  }
  for (const char* keyword : {"oneOf", "anyOf"}) {
    const auto alternatives = schema.find(keyword);
    if (alternatives == schema.end()) continue;
    std::vector<std::vector<ValidationError>> results;
    std::size_t matches = 0;
    for (const auto& alternative : *alternatives) {
      results.emplace_back();
      check(alternative, value, pointer, results.back());
      matches += results.back().empty();
    }
    const bool one_of = std::string(keyword) == "oneOf";
    if (matches == 1 || (!one_of && matches > 0)) continue;
    if (matches > 1) {
      fail("matches more than one alternative");
      continue;
    }
    // Report the alternative whose required keys are all present (the one the author meant), if any.
    std::optional<std::size_t> intended;
    for (std::size_t i = 0; i < alternatives->size() && value.is_object(); ++i) {
      const nlohmann::json& alternative = resolve((*alternatives)[i]);
      if (!alternative.contains("required")) continue;
      bool all_present = true;
      for (const auto& name : alternative["required"]) all_present &= value.contains(name.get<std::string>());
      if (all_present) {
        intended = i;
        break;
      }
    }
    if (intended) {
      errors.insert(errors.end(), results[*intended].begin(), results[*intended].end());
    } else {
      std::string expected;
      for (const auto& alternative : *alternatives) {
        const nlohmann::json& resolved = resolve(alternative);
        if (resolved.contains("required")) expected += (expected.empty() ? "" : " | ") + join(resolved["required"]);
      }
      fail(expected.empty() ? "matches none of the alternatives" : "expected one of the forms: " + expected);
    }
  }
}

std::pair<std::size_t, std::size_t> line_and_column(std::string_view text, std::size_t offset) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    column = text[i] == '\n' ? 1 : column + 1;
    line += text[i] == '\n';
  }
  return {line, column};
}

}  // namespace hrisim::core
