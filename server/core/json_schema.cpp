#include "core/json_schema.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <set>
#include <unordered_map>

#include "core/error.hpp"

namespace hrisim::core {
namespace {

const std::set<std::string> kSupportedKeywords = {
    "$schema", "$id", "$defs", "$ref", "$comment", "title", "description", "default", "examples", "deprecated", "x-unit",
    "type", "properties", "required", "additionalProperties", "minProperties", "maxProperties", "items", "minItems", "maxItems",
    "uniqueItems", "enum", "const", "minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum", "minLength", "maxLength",
    "pattern", "oneOf", "anyOf", "allOf", "if", "then", "else"};

/// Characters (Unicode code points) of UTF-8 text, as minLength and maxLength count them.
std::size_t code_points(const std::string& text) {
  return static_cast<std::size_t>(std::count_if(text.begin(), text.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
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

struct JsonSchema::Compiled {
  std::unordered_map<std::string, const nlohmann::json*> references;
  std::unordered_map<std::string, std::regex> patterns;
};

JsonSchema::JsonSchema(nlohmann::json schema)
    : document_(std::make_shared<const nlohmann::json>(std::move(schema))), schema_(document_.get()), compiled_(std::make_shared<Compiled>()) {
  check_keywords(*schema_, "#");
}

JsonSchema::JsonSchema(std::shared_ptr<const nlohmann::json> document, const std::string& pointer)
    : document_(std::move(document)), compiled_(std::make_shared<Compiled>()) {
  try {
    schema_ = &document_->at(nlohmann::json::json_pointer(pointer));
  } catch (const nlohmann::json::exception&) {
    throw Error(ErrorCode::internal, "no schema at #" + pointer);
  }
  check_keywords(*schema_, "#" + pointer);
}

void JsonSchema::check_keywords(const nlohmann::json& schema, const std::string& where) {
  if (!schema.is_object()) return;
  for (const auto& [key, value] : schema.items()) {
    if (!kSupportedKeywords.contains(key)) {
      throw Error(ErrorCode::internal, "schema keyword '" + key + "' at " + where + " is not supported");
    }
    if (key == "properties" || key == "$defs") {
      for (const auto& [name, sub] : value.items()) check_keywords(sub, where + "/" + key + "/" + pointer_token(name));
    } else if (key == "items" || key == "additionalProperties" || key == "if" || key == "then" || key == "else") {
      check_keywords(value, where + "/" + key);
    } else if (key == "oneOf" || key == "anyOf" || key == "allOf") {
      for (std::size_t i = 0; i < value.size(); ++i) check_keywords(value[i], where + "/" + key + "/" + std::to_string(i));
    } else if (key == "pattern" && !compiled_->patterns.contains(value.get<std::string>())) {
      try {
        compiled_->patterns.emplace(value.get<std::string>(), std::regex(value.get<std::string>(), std::regex::ECMAScript));
      } catch (const std::regex_error&) {
        throw Error(ErrorCode::internal, "schema pattern at " + where + " does not compile: " + value.get<std::string>());
      }
    } else if (key == "$ref") {
      const std::string ref = value.get<std::string>();
      if (compiled_->references.contains(ref)) continue;
      const nlohmann::json* target = nullptr;
      try {
        if (ref.starts_with("#")) target = &document_->at(nlohmann::json::json_pointer(ref.substr(1)));
      } catch (const nlohmann::json::exception&) {
      }
      if (target == nullptr) throw Error(ErrorCode::internal, "schema reference " + ref + " at " + where + " leads nowhere");
      compiled_->references.emplace(ref, target);
      check_keywords(*target, ref);
    }
  }
}

std::vector<ValidationError> JsonSchema::validate(const nlohmann::json& document) const {
  std::vector<ValidationError> errors;
  check(*schema_, document, "", errors);
  // A value a $ref and its siblings, or two forms, both find wrong is reported once.
  std::vector<ValidationError> distinct;
  for (ValidationError& error : errors) {
    if (std::find(distinct.begin(), distinct.end(), error) == distinct.end()) distinct.push_back(std::move(error));
  }
  return distinct;
}

const nlohmann::json& JsonSchema::resolve(const nlohmann::json& schema) const {
  const nlohmann::json* current = &schema;
  for (int depth = 0; current->is_object() && current->contains("$ref"); ++depth) {
    if (depth > 32) throw Error(ErrorCode::internal, "schema references loop at " + (*current)["$ref"].get<std::string>());
    current = compiled_->references.at((*current)["$ref"].get<std::string>());
  }
  return *current;
}

void JsonSchema::check(const nlohmann::json& schema, const nlohmann::json& value, const std::string& pointer,
                       std::vector<ValidationError>& errors) const {
  auto fail = [&](const std::string& message) { errors.push_back({pointer, message}); };
  if (schema.is_boolean()) {
    if (!schema.get<bool>()) fail("is not allowed here");
    return;
  }
  if (!schema.is_object()) return;
  // A $ref applies beside the schema's own keywords (2020-12), which are mostly a description.
  if (const auto ref = schema.find("$ref"); ref != schema.end()) check(*compiled_->references.at(ref->get<std::string>()), value, pointer, errors);

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
  if (value.is_string()) {
    const std::string& text = value.get_ref<const std::string&>();
    if (schema.contains("minLength") && code_points(text) < schema["minLength"].get<std::size_t>()) {
      fail(schema["minLength"].get<std::size_t>() == 1 ? "must not be empty"
                                                       : "must have at least " + schema["minLength"].dump() + " characters");
    }
    if (schema.contains("maxLength") && code_points(text) > schema["maxLength"].get<std::size_t>()) {
      fail("must have at most " + schema["maxLength"].dump() + " characters (got " + std::to_string(code_points(text)) + ")");
    }
    if (const auto pattern = schema.find("pattern");
        pattern != schema.end() && !std::regex_search(text, compiled_->patterns.at(pattern->get<std::string>()))) {
      fail("must match the pattern " + pattern->get<std::string>() + " (got " + value.dump() + ")");
    }
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
    if (schema.value("uniqueItems", false)) {
      for (std::size_t i = 1; i < value.size(); ++i) {
        const auto first = std::find(value.begin(), value.begin() + static_cast<std::ptrdiff_t>(i), value[i]);
        if (first != value.begin() + static_cast<std::ptrdiff_t>(i)) {
          errors.push_back({pointer + "/" + std::to_string(i), "repeats item " + std::to_string(first - value.begin()) + ": the items must be unique"});
          break;
        }
      }
    }
  }
  if (value.is_object()) {
    if (schema.contains("minProperties") && value.size() < schema["minProperties"].get<std::size_t>()) {
      fail("must have at least " + schema["minProperties"].dump() + " keys (got " + std::to_string(value.size()) + ")");
    }
    if (schema.contains("maxProperties") && value.size() > schema["maxProperties"].get<std::size_t>()) {
      fail("must have at most " + schema["maxProperties"].dump() + " keys (got " + std::to_string(value.size()) + ")");
    }
    if (const auto required = schema.find("required"); required != schema.end()) {
      for (const auto& name : *required) {
        // At the pointer the key would have, so that a client finds which one (an editor shows its parent).
        const std::string& key = name.get_ref<const std::string&>();
        if (!value.contains(key)) errors.push_back({pointer + "/" + pointer_token(key), "missing required key '" + key + "'"});
      }
    }
    const auto properties = schema.find("properties");
    const auto additional = schema.find("additionalProperties");
    for (const auto& [key, member] : value.items()) {
      const std::string member_pointer = pointer + "/" + pointer_token(key);
      if (properties != schema.end() && properties->contains(key)) {
        const nlohmann::json& property = (*properties)[key];
        if (property == false && schema.contains("description")) {
          // A key this form forbids: the form's description says why.
          errors.push_back({member_pointer, "is not allowed here: " + schema["description"].get<std::string>()});
        } else {
          check(property, member, member_pointer, errors);
        }
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
  if (const auto all = schema.find("allOf"); all != schema.end()) {
    for (const auto& part : *all) check(part, value, pointer, errors);
  }
  if (const auto condition = schema.find("if"); condition != schema.end()) {
    std::vector<ValidationError> unmet;
    check(*condition, value, pointer, unmet);
    const auto consequence = schema.find(unmet.empty() ? "then" : "else");
    if (consequence != schema.end()) check(*consequence, value, pointer, errors);
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
    // Or the one alternative of the value's type (an object where the others are null).
    for (std::size_t i = 0; i < alternatives->size() && !intended; ++i) {
      const nlohmann::json& alternative = resolve((*alternatives)[i]);
      const bool of_type = alternative.is_object() && alternative.contains("type") && alternative["type"].is_string() &&
                           type_matches(alternative["type"].get<std::string>(), value);
      const bool others_not = std::none_of(alternatives->begin(), alternatives->end(), [&](const nlohmann::json& other) {
        const nlohmann::json& resolved = resolve(other);
        return &resolved != &alternative && (!resolved.is_object() || !resolved.contains("type") || !resolved["type"].is_string() ||
                                             type_matches(resolved["type"].get<std::string>(), value));
      });
      if (of_type && others_not) intended = i;
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
