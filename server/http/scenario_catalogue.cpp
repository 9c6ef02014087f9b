#include "http/scenario_catalogue.hpp"

#include <algorithm>

#include "core/files.hpp"
#include "core/random.hpp"
#include "core/text.hpp"
#include "storage/store.hpp"

namespace hrisim::http {
namespace {

/// Memory a compiled upload holds, estimated: its grid's cells (the cell, its distance and nearest
/// obstacle: 9 bytes) and about eight bytes of parsed document per byte of source.
std::size_t approximate_bytes(const scenario::CompiledSource& compiled, std::size_t source_bytes) {
  constexpr std::size_t kBytesPerCell = 9, kDocumentBytesPerSourceByte = 8, kFixed = 64 * 1024;
  std::size_t cells = 0;
  if (compiled.model) cells = static_cast<std::size_t>(compiled.model->grid.width()) * static_cast<std::size_t>(compiled.model->grid.height());
  return cells * kBytesPerCell + source_bytes * kDocumentBytesPerSourceByte + kFixed;
}

}  // namespace

ScenarioCatalogue::ScenarioCatalogue(storage::Store* store, std::filesystem::path scenarios_dir, scenario::ScenarioLimits limits,
                                     std::size_t cache_bytes)
    : store_(store), dir_(std::move(scenarios_dir)), limits_(limits), cache_bytes_(cache_bytes) {
  std::error_code ignored;
  for (const auto& entry : std::filesystem::directory_iterator(dir_, ignored)) {
    if (entry.path().extension() != ".json") continue;
    std::string text;
    try {
      text = core::read_file(entry.path());
    } catch (const core::Error&) {
      continue;
    }
    auto compiled = std::make_shared<Entry>(Entry{"bundled", scenario::compile_source(text, scenario::SourceFormat::json, options()), "", ""});
    if (compiled->source.model) bundled_.emplace(entry.path().stem().string(), std::move(compiled));
  }
}

scenario::SourceOptions ScenarioCatalogue::options() const {
  scenario::SourceOptions options;
  options.import.map_search_path = {dir_};
  options.import.limits = limits_;
  options.load.map_search_path = {dir_};
  options.load.limits = limits_;
  return options;
}

std::shared_ptr<const ScenarioCatalogue::Entry> ScenarioCatalogue::find(const std::string& id) {
  if (const auto found = bundled_.find(id); found != bundled_.end()) return found->second;
  {
    std::lock_guard lock(mutex_);
    if (const auto found = uploaded_.find(id); found != uploaded_.end()) {
      uses_.splice(uses_.begin(), uses_, found->second.use);
      return found->second.entry;
    }
  }
  const auto record = store_->scenario(id);
  if (!record) return nullptr;
  // Compiled without the lock: two requests may both compile it; the cache keeps one.
  const auto format = scenario::source_format(record->format).value_or(scenario::SourceFormat::json);
  auto entry = std::make_shared<const Entry>(Entry{"uploaded", scenario::compile_source(record->source, format, options()), record->sha256, record->owner});
  std::lock_guard lock(mutex_);
  remember(id, entry, record->source.size());
  return entry;
}

std::shared_ptr<const ScenarioCatalogue::Entry> ScenarioCatalogue::find(const std::string& id, const Caller& caller) {
  auto entry = find(id);
  if (entry && entry->origin == "uploaded" && !visible_to(caller, entry->owner)) return nullptr;
  return entry;
}

void ScenarioCatalogue::remember(const std::string& id, std::shared_ptr<const Entry> entry, std::size_t source_bytes) {
  if (const auto found = uploaded_.find(id); found != uploaded_.end()) {
    held_bytes_ -= found->second.bytes;
    uses_.erase(found->second.use);
    uploaded_.erase(found);
  }
  const std::size_t bytes = approximate_bytes(entry->source, source_bytes);
  uses_.push_front(id);
  uploaded_.emplace(id, Cached{std::move(entry), bytes, uses_.begin()});
  held_bytes_ += bytes;
  // The newest stays even when it alone is larger than the cache: it is being used.
  while (held_bytes_ > cache_bytes_ && uses_.size() > 1) {
    const auto oldest = uploaded_.find(uses_.back());
    held_bytes_ -= oldest->second.bytes;
    uploaded_.erase(oldest);
    uses_.pop_back();
  }
}

std::size_t ScenarioCatalogue::cached_bytes() const {
  std::lock_guard lock(mutex_);
  return held_bytes_;
}

nlohmann::json ScenarioCatalogue::summary_of(const std::string& id, const Entry& entry) const {
  nlohmann::json summary = entry.source.model ? scenario::summarize(*entry.source.model) : nlohmann::json::object();
  summary["id"] = id;
  summary["origin"] = entry.origin;
  summary["format"] = scenario::to_string(entry.source.format);
  if (!entry.sha256.empty()) summary["sha256"] = entry.sha256;
  return summary;
}

nlohmann::json ScenarioCatalogue::summary(const std::string& id) {
  if (const auto found = bundled_.find(id); found != bundled_.end()) return summary_of(id, *found->second);
  const auto record = store_->scenario(id, false);
  if (!record) return nullptr;
  if (!record->summary.empty()) {
    nlohmann::json summary = nlohmann::json::parse(record->summary);
    summary["id"] = id;
    summary["origin"] = "uploaded";
    summary["format"] = scenario::to_string(scenario::source_format(record->format).value_or(scenario::SourceFormat::json));
    summary["sha256"] = record->sha256;
    return summary;
  }
  const auto entry = find(id);
  if (!entry) return nullptr;
  if (entry->source.model) store_->set_scenario_summary(id, core::json_text(scenario::summarize(*entry->source.model)));
  return summary_of(id, *entry);
}

std::vector<std::string> ScenarioCatalogue::page(const std::string& cursor, int limit, const Caller& caller) {
  std::vector<std::string> ids;
  for (const auto& [id, unused] : bundled_) {
    if (id > cursor) ids.push_back(id);
  }
  // Only uploads are listed; the snapshots runs keep of what they ran are found by id.
  const auto owner = caller.sees_all ? std::nullopt : std::optional(caller.owner);
  for (const auto& record : store_->scenarios(limit, cursor, std::string(1, kUploadedPrefix), owner)) ids.push_back(record.id);
  std::sort(ids.begin(), ids.end());
  if (static_cast<int>(ids.size()) > limit) ids.resize(static_cast<std::size_t>(limit));
  return ids;
}

std::string ScenarioCatalogue::store(const std::string& text, scenario::CompiledSource compiled, const std::string& owner) {
  storage::ScenarioRecord record;
  record.id = core::unguessable_id(kUploadedPrefix);
  record.name = compiled.model->name;
  record.format = std::string(scenario::to_string(compiled.format));
  record.source = text;
  record.summary = core::json_text(scenario::summarize(*compiled.model));
  record.owner = owner;
  record = store_->put_scenario(std::move(record));
  std::lock_guard lock(mutex_);
  remember(record.id, std::make_shared<const Entry>(Entry{"uploaded", std::move(compiled), record.sha256, owner}), text.size());
  return record.id;
}

}  // namespace hrisim::http
