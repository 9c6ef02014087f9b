#include "fuzz_server.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/text.hpp"
#include "http/api.hpp"
#include "runs/executor.hpp"
#include "storage/store.hpp"

namespace hrisim::fuzz {

struct Server::Parts {
  std::filesystem::path folder;
  std::unique_ptr<storage::Store> store;
  std::unique_ptr<runs::Executor> executor;
  std::shared_ptr<const http::Router> open, guarded;
  std::shared_ptr<http::WebSocketPeer> peer;
  std::string session;
};

namespace {

http::ApiContext context(storage::Store* store, runs::Executor* executor) {
  http::ApiContext context;
  context.store = store;
  context.executor = executor;
  context.web_root = HRISIM_WEB_DIR;
  context.scenarios_dir = HRISIM_SCENARIOS_DIR;
  context.scenario_limits.max_grid_cells = 1'000'000;
  context.scenario_limits.max_people = 200;
  context.scenario_limits.max_episode_ticks = 20'000;
  return context;
}

}  // namespace

Server::Server() : parts_(std::make_unique<Parts>()) {
  parts_->folder = std::filesystem::temp_directory_path() / ("hrisim-fuzz-" + std::to_string(getpid()));
  std::filesystem::create_directories(parts_->folder);
  parts_->store = std::make_unique<storage::Store>(parts_->folder / "fuzz.db");
  parts_->executor = std::make_unique<runs::Executor>(*parts_->store, 1);
  parts_->open = http::make_api_router(context(parts_->store.get(), parts_->executor.get()));
  http::ApiContext guarded = context(parts_->store.get(), parts_->executor.get());
  guarded.access.tokens = {http::parse_token("alice:alice-token-0123456789"), http::parse_token("reader:reader-token-0123456789:read"),
                           http::parse_token("root:root-token-0123456789:admin")};
  parts_->guarded = http::make_api_router(guarded);
}

Server::~Server() {
  parts_->peer.reset();
  parts_->executor.reset();
  parts_->store.reset();
  std::error_code ignored;
  std::filesystem::remove_all(parts_->folder, ignored);
}

http::Response Server::settle(http::Response response) { return http::complete(std::move(response), "a fuzzed request"); }

http::Response Server::answer(http::Request request) {
  const bool with_token = request.headers.contains("authorization");
  const bool run = request.method == "POST" && request.path == "/api/v1/runs";
  http::Response response = settle((with_token ? parts_->guarded : parts_->open)->dispatch(std::move(request)));
  if (run && response.status == 201) {
    const auto id = nlohmann::json::parse(response.body).value("id", "");
    if (!id.empty()) {
      http::Request cancel;
      cancel.method = "POST";
      cancel.path = "/api/v1/runs/" + id + "/cancel";
      cancel.headers["content-type"] = "application/json";
      settle(parts_->open->dispatch(std::move(cancel)));
      parts_->executor->wait(id);
    }
  }
  return response;
}

http::WebSocketPeer& Server::socket() {
  if (parts_->peer) {
    http::Request status;
    status.method = "GET";
    status.path = "/api/v1/sessions/" + parts_->session;
    const http::Response reply = settle(parts_->open->dispatch(status));
    if (reply.status == 200 && nlohmann::json::parse(reply.body).value("status", "") == "running") return *parts_->peer;
    http::Request remove;
    remove.method = "DELETE";
    remove.path = status.path;
    settle(parts_->open->dispatch(remove));
  }
  http::Request create;
  create.method = "POST";
  create.path = "/api/v1/sessions";
  create.headers["content-type"] = "application/json";
  create.body = R"({"scenario": "elevator"})";
  const http::Response created = settle(parts_->open->dispatch(create));
  if (created.status != 201) {
    std::fprintf(stderr, "fuzz: cannot create the session: %s\n", created.body.c_str());
    std::abort();
  }
  parts_->session = nlohmann::json::parse(created.body)["id"];
  http::Request upgrade;
  upgrade.method = "GET";
  upgrade.path = "/api/v1/sessions/" + parts_->session + "/ws";
  upgrade.headers["upgrade"] = "websocket";
  auto outcome = parts_->open->upgrade(upgrade);
  parts_->peer = std::get<std::shared_ptr<http::WebSocketPeer>>(outcome);
  return *parts_->peer;
}

Server& server() {
  static Server instance;
  return instance;
}

http::Request parse_request(std::string_view text) {
  http::Request request;
  const auto line_end = text.find('\n');
  std::string_view first = text.substr(0, line_end);
  if (first.ends_with('\r')) first.remove_suffix(1);
  const auto space = first.find(' ');
  request.method = std::string(first.substr(0, space));
  std::string_view target = space == std::string_view::npos ? std::string_view("/") : first.substr(space + 1);
  const auto query = target.find('?');
  request.query = query == std::string_view::npos ? "" : std::string(target.substr(query + 1));
  try {
    request.path = http::percent_decode(target.substr(0, query));
  } catch (const core::Error&) {
    request.path = "/";
  }
  if (request.path.empty() || request.path.front() != '/') request.path = "/" + request.path;
  std::size_t at = line_end == std::string_view::npos ? text.size() : line_end + 1;
  while (at < text.size()) {
    const auto end = std::min(text.find('\n', at), text.size());
    std::string_view line = text.substr(at, end - at);
    at = end + 1;
    if (line.ends_with('\r')) line.remove_suffix(1);
    if (line.empty()) break;
    const auto colon = line.find(':');
    const std::string name = core::lower_case(std::string(line.substr(0, colon)));
    std::string_view value = colon == std::string_view::npos ? std::string_view() : line.substr(colon + 1);
    while (value.starts_with(' ')) value.remove_prefix(1);
    request.headers[name] = std::string(value);
  }
  if (at < text.size()) request.body = std::string(text.substr(at));
  return request;
}

void check_reply(const http::Response& response) {
  if (response.status == 500 && response.body.find("\"internal\"") != std::string::npos) {
    std::fprintf(stderr, "fuzz: an internal error: %s\n", response.body.c_str());
    std::abort();
  }
}

}  // namespace hrisim::fuzz
