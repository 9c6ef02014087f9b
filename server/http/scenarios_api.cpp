#include "http/scenarios_api.hpp"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <map>
#include <mutex>
#include <random>
#include <sstream>

#include "scenario/source.hpp"
#include "storage/store.hpp"

namespace hrisim::http {
namespace {

using nlohmann::json;

/// The value of `key` in a raw query string (no percent-decoding: the values used here are plain).
std::optional<std::string> query_value(const std::string& query, const std::string& key) {
  std::istringstream in(query);
  std::string pair;
  while (std::getline(in, pair, '&')) {
    const std::size_t equals = pair.find('=');
    if (pair.substr(0, equals) == key) return equals == std::string::npos ? "" : pair.substr(equals + 1);
  }
  return std::nullopt;
}

/// An uploaded scenario's id: "u" and 128 random bits in hex, so ids cannot be guessed or collide.
std::string new_scenario_id() {
  std::random_device device;
  std::ostringstream id;
  id << 'u' << std::hex;
  for (int i = 0; i < 4; ++i) id << std::setw(8) << std::setfill('0') << device();
  return id.str();
}

/// The scenarios the server knows: bundled files (id = file stem) compiled once at start, uploaded
/// ones compiled on first use and kept.
class Catalogue {
 public:
  Catalogue(storage::Store* store, std::filesystem::path scenarios_dir) : store_(store), dir_(std::move(scenarios_dir)) {
    std::error_code ignored;
    for (const auto& entry : std::filesystem::directory_iterator(dir_, ignored)) {
      if (entry.path().extension() != ".json") continue;
      std::ifstream in(entry.path(), std::ios::binary);
      std::ostringstream text;
      text << in.rdbuf();
      Entry compiled{"bundled", scenario::compile_source(text.str(), scenario::SourceFormat::json, options()), ""};
      if (compiled.source.model) bundled_.emplace(entry.path().stem().string(), std::move(compiled));
    }
  }

  scenario::SourceOptions options() const {
    scenario::SourceOptions options;
    options.import.map_search_path = {dir_};
    options.load.map_search_path = {dir_};
    return options;
  }

  struct Entry {
    std::string origin;  ///< "bundled" or "uploaded"
    scenario::CompiledSource source;
    std::string sha256;
  };

  /// The scenario with this id, or null.
  const Entry* find(const std::string& id) {
    if (const auto found = bundled_.find(id); found != bundled_.end()) return &found->second;
    std::lock_guard lock(mutex_);
    if (const auto found = uploaded_.find(id); found != uploaded_.end()) return &found->second;
    const auto record = store_->scenario(id);
    if (!record) return nullptr;
    const auto format = scenario::source_format(record->format).value_or(scenario::SourceFormat::json);
    Entry entry{"uploaded", scenario::compile_source(record->source, format, options()), record->sha256};
    return &uploaded_.emplace(id, std::move(entry)).first->second;
  }

  json summary(const std::string& id, const Entry& entry) const {
    json summary = entry.source.model ? scenario::summarize(*entry.source.model) : json::object();
    summary["id"] = id;
    summary["origin"] = entry.origin;
    summary["format"] = scenario::to_string(entry.source.format);
    if (!entry.sha256.empty()) summary["sha256"] = entry.sha256;
    return summary;
  }

  /// A page of ids after `cursor`, bundled and uploaded merged in id order.
  std::vector<std::string> page(const std::string& cursor, int limit) {
    std::vector<std::string> ids;
    for (const auto& [id, unused] : bundled_) {
      if (id > cursor) ids.push_back(id);
    }
    for (const auto& record : store_->scenarios(limit, cursor)) ids.push_back(record.id);
    std::sort(ids.begin(), ids.end());
    if (static_cast<int>(ids.size()) > limit) ids.resize(static_cast<std::size_t>(limit));
    return ids;
  }

  std::string store(const std::string& text, scenario::CompiledSource compiled) {
    storage::ScenarioRecord record;
    record.id = new_scenario_id();
    record.name = compiled.model->name;
    record.format = std::string(scenario::to_string(compiled.format));
    record.source = text;
    record = store_->put_scenario(std::move(record));
    std::lock_guard lock(mutex_);
    uploaded_.emplace(record.id, Entry{"uploaded", std::move(compiled), record.sha256});
    return record.id;
  }

 private:
  storage::Store* store_;
  std::filesystem::path dir_;
  std::map<std::string, Entry> bundled_;
  std::mutex mutex_;
  std::map<std::string, Entry> uploaded_;
};

/// The body's format: ?format= when given, else the content type, else its first character.
scenario::SourceFormat body_format(const Request& request) {
  if (const auto named = query_value(request.query, "format")) {
    const auto format = scenario::source_format(*named);
    if (!format) {
      throw core::Error(core::ErrorCode::bad_request, "format '" + *named + "' is not json, imhus or pedsim", {{"parameter", "format"}});
    }
    return *format;
  }
  const auto type = request.headers.find("content-type");
  const std::string content_type = type == request.headers.end() ? "" : type->second;
  if (content_type.starts_with("application/json")) return scenario::SourceFormat::json;
  return scenario::detect_source_format(request.body);
}

/// Refuses JSON nested deeper than kMaxJsonDepth before anything parses it (strings skipped).
void check_nesting(const std::string& text) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) {
        throw core::Error(core::ErrorCode::bad_request, "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels",
                          {{"limit", kMaxJsonDepth}});
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

/// The body compiled as the format it is in.
scenario::CompiledSource compile_body(const Request& request, const Catalogue& catalogue) {
  const scenario::SourceFormat format = body_format(request);
  if (format == scenario::SourceFormat::json) check_nesting(request.body);
  return scenario::compile_source(request.body, format, catalogue.options());
}

json issues(const std::vector<scenario::SourceIssue>& list) {
  json result = json::array();
  for (const auto& issue : list) result.push_back(issue.to_json());
  return result;
}

}  // namespace

void add_scenario_routes(Router& router, storage::Store* store, const std::filesystem::path& scenarios_dir) {
  auto catalogue = std::make_shared<Catalogue>(store, scenarios_dir);

  router.add("GET", "/api/v1/scenarios", [catalogue](const Request& request) {
    int limit = kDefaultPageSize;
    if (const auto text = query_value(request.query, "limit")) {
      try {
        std::size_t used = 0;
        limit = std::stoi(*text, &used);
        if (used != text->size()) throw std::invalid_argument("trailing characters");
      } catch (const std::exception&) {
        limit = 0;
      }
      if (limit < 1 || limit > kMaxPageSize) {
        throw core::Error(core::ErrorCode::bad_request, "limit must be an integer from 1 to " + std::to_string(kMaxPageSize),
                          {{"parameter", "limit"}});
      }
    }
    const std::string cursor = query_value(request.query, "cursor").value_or("");
    const auto ids = catalogue->page(cursor, limit + 1);
    json items = json::array();
    for (std::size_t i = 0; i < ids.size() && static_cast<int>(i) < limit; ++i) {
      if (const auto* entry = catalogue->find(ids[i])) items.push_back(catalogue->summary(ids[i], *entry));
    }
    json page{{"items", items}, {"next_cursor", nullptr}};
    if (static_cast<int>(ids.size()) > limit) page["next_cursor"] = ids[static_cast<std::size_t>(limit) - 1];
    return Response::json(200, page);
  });

  router.add("GET", "/api/v1/scenarios/{id}", [catalogue](const Request& request) {
    const std::string& id = request.path_params.at("id");
    const auto* entry = catalogue->find(id);
    if (!entry) throw core::Error(core::ErrorCode::not_found, "no scenario '" + id + "'", {{"id", id}});
    return Response::json(200, entry->source.document);
  });

  router.add("POST", "/api/v1/scenarios/validate", [catalogue](const Request& request) {
    const auto compiled = compile_body(request, *catalogue);
    json reply{{"valid", compiled.errors.empty()},
               {"format", scenario::to_string(compiled.format)},
               {"errors", issues(compiled.errors)},
               {"warnings", issues(compiled.warnings)}};
    if (compiled.model) reply["summary"] = scenario::summarize(*compiled.model);
    return Response::json(200, reply);
  });

  router.add("POST", "/api/v1/scenarios", [catalogue](const Request& request) {
    auto compiled = compile_body(request, *catalogue);
    if (!compiled.errors.empty()) {
      throw core::Error(core::ErrorCode::bad_request, "the scenario is not valid: nothing was stored",
                        {{"format", scenario::to_string(compiled.format)}, {"errors", issues(compiled.errors)}});
    }
    const json warnings = issues(compiled.warnings);
    const std::string id = catalogue->store(request.body, std::move(compiled));
    Response response = Response::json(201, {{"summary", catalogue->summary(id, *catalogue->find(id))}, {"warnings", warnings}});
    response.headers.emplace_back("Location", "/api/v1/scenarios/" + id);
    return response;
  });
}

}  // namespace hrisim::http
