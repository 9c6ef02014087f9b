// Fuzz target: a snapshot file (docs/api.md#snapshot-files) given to POST /api/v1/sessions {"snapshot"}:
// its header read, its scenario found, its input log read against the scenario and simulated again,
// its state hash checked — through the router of `hrisim serve`, as a client's file arrives. A session
// the file starts is ended again, so that every input finds room for one.
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "fuzz_server.hpp"
#include "http/router.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nlohmann::json file = nlohmann::json::parse(std::string_view(reinterpret_cast<const char*>(data), size), nullptr, false);
  if (file.is_discarded()) return 0;  // not JSON: the body's parser is fuzz_http_request's
  hrisim::fuzz::Server& server = hrisim::fuzz::server();
  hrisim::http::Request create;
  create.method = "POST";
  create.path = "/api/v1/sessions";
  create.headers["content-type"] = "application/json";
  create.body = nlohmann::json{{"snapshot", file}}.dump();
  const hrisim::http::Response created = server.answer(std::move(create));
  hrisim::fuzz::check_reply(created);
  if (created.status == 201) {
    hrisim::http::Request end;
    end.method = "DELETE";
    end.path = "/api/v1/sessions/" + nlohmann::json::parse(created.body).value("id", "");
    hrisim::fuzz::check_reply(server.answer(std::move(end)));
  }
  return 0;
}
