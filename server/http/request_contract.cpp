#include "http/request_contract.hpp"

#include <cctype>

#include "core/embedded.hpp"
#include "core/error.hpp"

namespace hrisim::http {
namespace embedded {
extern const std::pair<std::string_view, std::string_view> kEmbedded[];
extern const int kEmbeddedCount;
}  // namespace embedded

namespace {

using nlohmann::json;

/// Rewrites every $ref of `part` (the description kept at /`name` of the joint document) to point
/// into the joint document: "#/x" to "#/name/x", and asyncapi's "openapi.yaml#/x" to "#/openapi/x".
void localize_references(json& part, const std::string& name) {
  if (part.is_array()) {
    for (json& item : part) localize_references(item, name);
    return;
  }
  if (!part.is_object()) return;
  for (auto& [key, value] : part.items()) {
    if (key == "$ref" && value.is_string()) {
      const std::string ref = value;
      const std::size_t hash = ref.find('#');
      const std::string file = ref.substr(0, hash);
      const std::string document = file.empty() ? name : file == "openapi.yaml" ? "openapi" : "";
      if (hash == std::string::npos || document.empty()) throw core::Error(core::ErrorCode::internal, "unsupported reference " + ref + " in " + name);
      value = "#/" + document + ref.substr(hash + 1);
    } else {
      localize_references(value, name);
    }
  }
}

std::string upper(std::string text) {
  for (char& c : text) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return text;
}

}  // namespace

std::string_view api_file(std::string_view name) {
  const std::string_view contents = core::find_embedded({embedded::kEmbedded, static_cast<std::size_t>(embedded::kEmbeddedCount)}, name);
  if (contents.empty()) throw core::Error(core::ErrorCode::internal, "embedded file " + std::string(name) + " is missing");
  return contents;
}

RequestContract::RequestContract(json openapi, json asyncapi) {
  localize_references(openapi, "openapi");
  localize_references(asyncapi, "asyncapi");
  descriptions_ = std::make_shared<const json>(json{{"openapi", std::move(openapi)}, {"asyncapi", std::move(asyncapi)}});
  const json& paths = (*descriptions_)["openapi"].at("paths");
  for (const auto& [path, operations] : paths.items()) {
    for (const auto& [method, operation] : operations.items()) {
      if (!operation.is_object() || method == "parameters") continue;
      Operation described;
      const json content = operation.contains("requestBody") ? operation["requestBody"].value("content", json::object()) : json::object();
      if (content.size() == 1 && content.contains("application/json")) {
        const std::string at = "/openapi/paths/" + core::pointer_token(path) + "/" + method + "/requestBody/content/application~1json/schema";
        bodies_.push_back(std::make_unique<core::JsonSchema>(descriptions_, at));
        described.body = bodies_.back().get();
      }
      operations_.emplace(std::pair{upper(method), path}, described);
    }
  }
  // The messages a client sends: those of the operations the server receives.
  for (const auto& [name, operation] : (*descriptions_)["asyncapi"].at("operations").items()) {
    if (operation.value("action", "") != "receive") continue;
    for (const json& reference : operation.at("messages")) {
      // "#/asyncapi/channels/session/messages/step" → the channel's $ref to the message itself.
      const json& channel_message = descriptions_->at(json::json_pointer(reference.at("$ref").get<std::string>().substr(1)));
      const std::string at = channel_message.at("$ref").get<std::string>().substr(1) + "/payload";
      const std::string type = descriptions_->at(json::json_pointer(at + "/properties/type/const"));
      messages_.emplace(type, core::JsonSchema(descriptions_, at));
    }
  }
}

const RequestContract& RequestContract::embedded() {
  static const RequestContract contract(json::parse(api_file("openapi.json")), json::parse(api_file("asyncapi.json")));
  return contract;
}

const RequestContract::Operation* RequestContract::operation(std::string_view method, std::string_view pattern) const {
  const auto found = operations_.find(std::pair{std::string(method), std::string(pattern)});
  return found == operations_.end() ? nullptr : &found->second;
}

const core::JsonSchema* RequestContract::message(std::string_view type) const {
  const auto found = messages_.find(type);
  return found == messages_.end() ? nullptr : &found->second;
}

void check_against(const core::JsonSchema& schema, const json& value) {
  const std::vector<core::ValidationError> errors = schema.validate(value);
  if (errors.empty()) return;
  json listed = json::array();
  for (const auto& [pointer, message] : errors) listed.push_back({{"pointer", pointer}, {"message", message}});
  const std::string first = (errors[0].pointer.empty() ? "the body" : errors[0].pointer) + ": " + errors[0].message;
  throw core::Error(core::ErrorCode::bad_request, errors.size() == 1 ? first : first + " (and " + std::to_string(errors.size() - 1) + " more)",
                    {{"errors", listed}, {"pointer", errors[0].pointer}});
}

}  // namespace hrisim::http
