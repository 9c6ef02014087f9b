#include "http/scenario_catalogue.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <fstream>

#include "core/files.hpp"
#include "core/random.hpp"
#include "core/sha256.hpp"
#include "core/text.hpp"
#include "storage/store.hpp"

namespace hrisim::http {

std::string ScenarioCatalogue::Entry::content_sha256() const {
  return sha256.empty() ? core::sha256_hex(core::json_text(source.document)) : sha256;
}

namespace {

/// Values (objects, arrays, members, numbers, strings) of a JSON document, counted without recursion.
std::size_t values_in(const nlohmann::json& document) {
  std::size_t values = 0;
  std::vector<const nlohmann::json*> pending{&document};
  while (!pending.empty()) {
    const nlohmann::json* value = pending.back();
    pending.pop_back();
    ++values;
    if (value->is_structured()) {
      for (const auto& child : *value) pending.push_back(&child);
    }
  }
  return values;
}

/// Memory a compiled upload holds, estimated from what its source expands to, not from its bytes (a
/// YAML file's aliases expand a few bytes into thousands of goals): its grid's cells (the cell, its
/// distance and nearest obstacle: 9 bytes) and the values of its native document, each with its share
/// of the compiled model (measured in docs/limits.md).
std::size_t approximate_bytes(const scenario::CompiledSource& compiled) {
  constexpr std::size_t kBytesPerCell = 9, kBytesPerDocumentValue = 256, kFixed = 64 * 1024;
  std::size_t cells = 0;
  if (compiled.model) cells = static_cast<std::size_t>(compiled.model->grid.width()) * static_cast<std::size_t>(compiled.model->grid.height());
  return cells * kBytesPerCell + values_in(compiled.document) * kBytesPerDocumentValue + kFixed;
}

/// `text` without any mention of `folder` (a private path of this process), so that messages name files
/// as the upload did.
std::string without_folder(std::string text, const std::filesystem::path& folder) {
  const std::string prefix = folder.string() + "/";
  for (std::size_t at = text.find(prefix); at != std::string::npos; at = text.find(prefix, at)) text.erase(at, prefix.size());
  return text;
}

}  // namespace

std::optional<NestedFile> nested_upload_file(const std::map<std::string, std::string>& files) {
  for (const auto& [path, unused] : files) {
    for (std::size_t slash = path.find('/'); slash != std::string::npos; slash = path.find('/', slash + 1)) {
      if (files.contains(path.substr(0, slash))) return NestedFile{path.substr(0, slash), path};
    }
  }
  return std::nullopt;
}

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
    auto compiled = std::make_shared<Entry>(Entry{"bundled", scenario::compile_source(text, scenario::SourceFormat::json, options_with({})), "", "", {}});
    if (compiled->source.model) bundled_.emplace(entry.path().stem().string(), std::move(compiled));
  }
}

ScenarioCatalogue::~ScenarioCatalogue() {
  std::error_code ignored;
  if (!files_root_.empty()) std::filesystem::remove_all(files_root_, ignored);
}

scenario::SourceOptions ScenarioCatalogue::options_with(const std::filesystem::path& files) const {
  scenario::SourceOptions options;
  options.import.map_search_path = {dir_};
  options.load.map_search_path = {dir_};
  if (!files.empty()) {
    options.import.map_search_path.insert(options.import.map_search_path.begin(), files);
    options.load.map_search_path.insert(options.load.map_search_path.begin(), files);
  }
  options.import.limits = limits_;
  options.load.limits = limits_;
  return options;
}

scenario::SourceOptions ScenarioCatalogue::options(const Entry& entry) const { return options_with(entry.files); }

std::filesystem::path ScenarioCatalogue::write_files(const std::string& name, const std::map<std::string, std::string>& files) {
  if (files.empty()) return {};
  // The folder is named by the scenario's id: one plain name, whatever stored the id.
  if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos || name.find('\0') != std::string::npos) {
    throw core::Error(core::ErrorCode::bad_request, "a scenario with files needs an id that names a folder");
  }
  namespace fs = std::filesystem;
  fs::path root;
  {
    std::lock_guard lock(mutex_);
    if (files_root_.empty()) {
      files_root_ = core::make_private_temp_folder(kFilesFolderPrefix);
    }
    root = files_root_;
  }
  const fs::path folder = root / name;
  if (fs::is_directory(folder)) return folder;
  if (const auto nested = nested_upload_file(files)) {
    throw core::Error(core::ErrorCode::bad_request, "file '" + nested->inside + "' lies inside file '" + nested->file + "' of the upload",
                      {{"pointer", "/files/" + core::pointer_token(nested->inside)}});
  }
  // Written aside, then renamed into place: two requests compiling the same upload see whole folders.
  // Whatever fails, the folder aside goes.
  const fs::path partial = root / (name + ".partial-" + core::unguessable_id('f'));
  std::error_code failed;
  for (const auto& [path, bytes] : files) {
    // Whatever stored them (an upload, an import): never a file outside the scenario's folder.
    if (const std::string problem = storage::scenario_file_path_problem(path); !problem.empty()) {
      std::error_code ignored;
      fs::remove_all(partial, ignored);
      throw core::Error(core::ErrorCode::bad_request, "the scenario's file '" + path.substr(0, 64) + "': " + problem);
    }
    const fs::path file = partial / path;
    fs::create_directories(file.parent_path(), failed);
    std::ofstream out(file, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (failed || !out.flush()) {
      std::error_code ignored;
      fs::remove_all(partial, ignored);
      throw core::Error(core::ErrorCode::internal, "the files uploaded with the scenario could not be written");
    }
  }
  std::error_code exists;
  fs::rename(partial, folder, exists);
  if (exists) fs::remove_all(partial, exists);
  return folder;
}

scenario::CompiledSource ScenarioCatalogue::compile(const Upload& upload, const std::filesystem::path& files) {
  scenario::CompiledSource compiled = scenario::compile_source(upload.text, upload.format, options_with(files));
  if (!files.empty()) {
    for (auto* issues : {&compiled.errors, &compiled.warnings}) {
      for (scenario::SourceIssue& issue : *issues) issue.message = without_folder(std::move(issue.message), files);
    }
  }
  return compiled;
}

scenario::CompiledSource ScenarioCatalogue::check(const Upload& upload, const AlsoCheck& also) {
  const std::filesystem::path files = write_files("check-" + core::unguessable_id('f'), upload.files);
  const auto remove_files = [&files] {
    std::error_code ignored;
    if (!files.empty()) std::filesystem::remove_all(files, ignored);
  };
  try {
    scenario::CompiledSource compiled = compile(upload, files);
    if (also) {
      try {
        also(compiled, options_with(files));
      } catch (const core::Error& e) {
        throw core::Error(e.code(), files.empty() ? e.what() : without_folder(e.what(), files), e.details());
      }
    }
    remove_files();
    return compiled;
  } catch (...) {
    remove_files();
    throw;
  }
}

ScenarioCatalogue::Added ScenarioCatalogue::add(const Upload& upload, const std::string& owner, scenario::CompiledSource& compiled) {
  const std::string format(scenario::to_string(upload.format));
  const std::string sha256 = storage::scenario_sha256(upload.text, upload.files);
  if (const auto existing = store_->scenario_with_content(sha256, format, owner, std::string(1, kUploadedPrefix))) {
    if (const auto entry = find(*existing)) {
      store_->set_scenario_listed(*existing, true);
      compiled = entry->source;
      return {*existing, true};
    }
  }
  storage::ScenarioRecord record;
  record.id = core::unguessable_id(kUploadedPrefix);
  const std::filesystem::path files = write_files(record.id, upload.files);
  compiled = compile(upload, files);
  if (!compiled.errors.empty()) {
    std::error_code ignored;
    if (!files.empty()) std::filesystem::remove_all(files, ignored);
    return {};
  }
  record.name = compiled.model->name;
  record.format = std::string(scenario::to_string(compiled.format));
  record.source = upload.text;
  record.summary = core::json_text(scenario::summarize(*compiled.model));
  record.owner = owner;
  record.files = upload.files;
  record = store_->put_scenario(std::move(record));
  std::lock_guard lock(mutex_);
  remember(record.id, std::make_shared<const Entry>(Entry{"uploaded", compiled, record.sha256, owner, files}));
  return {record.id, false};
}

bool ScenarioCatalogue::remove(const std::string& id, const Caller& caller) {
  if (bundled_.contains(id)) {
    throw core::Error(core::ErrorCode::conflict, "scenario '" + id + "' is bundled with the server: only uploads can be deleted", {{"id", id}});
  }
  const auto record = store_->scenario(id, false);
  if (!record || id.empty() || id.front() != kUploadedPrefix || !visible_to(caller, record->owner)) {
    throw core::Error(core::ErrorCode::not_found, "no scenario '" + id + "'", {{"id", id}});
  }
  if (!store_->delete_scenario(id)) return false;  // runs ran it: unlisted, kept for them
  std::lock_guard lock(mutex_);
  const auto found = uploaded_.find(id);
  const std::filesystem::path files = found == uploaded_.end() ? std::filesystem::path() : found->second.entry->files;
  forget(id);
  std::error_code ignored;
  if (!files.empty()) std::filesystem::remove_all(files, ignored);
  return true;
}

void ScenarioCatalogue::forget(const std::string& id) {
  const auto found = uploaded_.find(id);
  if (found == uploaded_.end()) return;
  held_bytes_ -= found->second.bytes;
  uses_.erase(found->second.use);
  uploaded_.erase(found);
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
  const Upload upload{record->source, scenario::source_format(record->format).value_or(scenario::SourceFormat::json), record->files};
  const std::filesystem::path files = write_files(id, upload.files);
  auto entry = std::make_shared<const Entry>(Entry{"uploaded", compile(upload, files), record->sha256, record->owner, files});
  std::lock_guard lock(mutex_);
  remember(id, entry);
  return entry;
}

std::shared_ptr<const ScenarioCatalogue::Entry> ScenarioCatalogue::find(const std::string& id, const Caller& caller) {
  auto entry = find(id);
  if (entry && entry->origin == "uploaded" && !visible_to(caller, entry->owner)) return nullptr;
  return entry;
}

void ScenarioCatalogue::remember(const std::string& id, std::shared_ptr<const Entry> entry) {
  forget(id);
  const std::size_t bytes = approximate_bytes(entry->source);
  uses_.push_front(id);
  uploaded_.emplace(id, Cached{std::move(entry), bytes, uses_.begin()});
  held_bytes_ += bytes;
  // The newest stays even when it alone is larger than the cache: it is being used.
  while (held_bytes_ > cache_bytes_ && uses_.size() > 1) forget(std::string(uses_.back()));  // a copy: forget erases the list entry
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

}  // namespace hrisim::http
