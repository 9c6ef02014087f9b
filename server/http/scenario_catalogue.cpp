#include "http/scenario_catalogue.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "core/random.hpp"
#include "storage/store.hpp"

namespace hrisim::http {
ScenarioCatalogue::ScenarioCatalogue(storage::Store* store, std::filesystem::path scenarios_dir)
    : store_(store), dir_(std::move(scenarios_dir)) {
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

scenario::SourceOptions ScenarioCatalogue::options() const {
  scenario::SourceOptions options;
  options.import.map_search_path = {dir_};
  options.load.map_search_path = {dir_};
  return options;
}

const ScenarioCatalogue::Entry* ScenarioCatalogue::find(const std::string& id) {
  if (const auto found = bundled_.find(id); found != bundled_.end()) return &found->second;
  std::lock_guard lock(mutex_);
  if (const auto found = uploaded_.find(id); found != uploaded_.end()) return &found->second;
  const auto record = store_->scenario(id);
  if (!record) return nullptr;
  const auto format = scenario::source_format(record->format).value_or(scenario::SourceFormat::json);
  Entry entry{"uploaded", scenario::compile_source(record->source, format, options()), record->sha256};
  return &uploaded_.emplace(id, std::move(entry)).first->second;
}

nlohmann::json ScenarioCatalogue::summary(const std::string& id, const Entry& entry) const {
  nlohmann::json summary = entry.source.model ? scenario::summarize(*entry.source.model) : nlohmann::json::object();
  summary["id"] = id;
  summary["origin"] = entry.origin;
  summary["format"] = scenario::to_string(entry.source.format);
  if (!entry.sha256.empty()) summary["sha256"] = entry.sha256;
  return summary;
}

std::vector<std::string> ScenarioCatalogue::page(const std::string& cursor, int limit) {
  std::vector<std::string> ids;
  for (const auto& [id, unused] : bundled_) {
    if (id > cursor) ids.push_back(id);
  }
  // Only uploads are listed; the snapshots runs keep of what they ran are found by id.
  for (const auto& record : store_->scenarios(limit, cursor, std::string(1, kUploadedPrefix))) ids.push_back(record.id);
  std::sort(ids.begin(), ids.end());
  if (static_cast<int>(ids.size()) > limit) ids.resize(static_cast<std::size_t>(limit));
  return ids;
}

std::string ScenarioCatalogue::store(const std::string& text, scenario::CompiledSource compiled) {
  storage::ScenarioRecord record;
  record.id = core::unguessable_id(kUploadedPrefix);
  record.name = compiled.model->name;
  record.format = std::string(scenario::to_string(compiled.format));
  record.source = text;
  record = store_->put_scenario(std::move(record));
  std::lock_guard lock(mutex_);
  uploaded_.emplace(record.id, Entry{"uploaded", std::move(compiled), record.sha256});
  return record.id;
}

}  // namespace hrisim::http
