#pragma once
// The request contract, written once: api/openapi.yaml's JSON request bodies and api/asyncapi.yaml's
// messages a client sends are the schemas every body and message is checked against before a handler
// runs (with core::JsonSchema, as scenarios are against api/scenario.schema.json), every error at once
// with its JSON pointer. Handlers then read values the contract guarantees, and check only what a
// schema cannot say (a tick not yet simulated, a scenario that exists).
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/json_schema.hpp"

namespace hrisim::http {

class RequestContract {
 public:
  /// One operation of the OpenAPI description.
  struct Operation {
    /// The schema of its body when it takes a JSON body only; null for no body, or a body of other or
    /// several media types (a scenario upload, checked by the scenario schema with lines; a database).
    const core::JsonSchema* body = nullptr;
  };

  /// Both descriptions as JSON (converted from YAML at build time); throws core::Error(internal) when a
  /// schema uses a keyword the checker does not support, so the contract never checks less than it says.
  RequestContract(nlohmann::json openapi, nlohmann::json asyncapi);

  /// The contract built into the server (read once).
  static const RequestContract& embedded();

  /// The operation `method` `pattern` (a path as the description writes it, /api/v1/sessions/{id}),
  /// or null when the description has none.
  const Operation* operation(std::string_view method, std::string_view pattern) const;

  /// The schema of a WebSocket message of `type` a client sends on a session's socket, or null.
  const core::JsonSchema* message(std::string_view type) const;

 private:
  std::shared_ptr<const nlohmann::json> descriptions_;  ///< {"openapi": …, "asyncapi": …}, $refs made local to it
  std::map<std::pair<std::string, std::string>, Operation, std::less<>> operations_;
  std::map<std::string, core::JsonSchema, std::less<>> messages_;
  std::vector<std::unique_ptr<core::JsonSchema>> bodies_;
};

/// An API description file built into the server: openapi.yaml, openapi.json or asyncapi.json.
std::string_view api_file(std::string_view name);

/// A JSON body or message checked against `schema`: core::Error(bad_request) naming every error
/// (details.errors: [{pointer, message}], details.pointer: the first's) when there are any.
void check_against(const core::JsonSchema& schema, const nlohmann::json& value);

}  // namespace hrisim::http
