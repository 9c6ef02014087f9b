#include "runs/merge.hpp"

#include <algorithm>
#include <map>
#include <set>

#include "core/error.hpp"
#include "core/random.hpp"
#include "core/sha256.hpp"
#include "runs/imported.hpp"

namespace hrisim::runs {
namespace {

using nlohmann::json;

std::string text_of(const json& value) {
  if (value.is_string()) return value.get<std::string>();
  return value.is_null() ? "none" : value.dump();
}

/// What a run's config says of the whole run it is a shard of: {count, of_seeds, index (a shard's) or
/// merged (the shards merged so far)}; null for a run run whole.
json sharding_of(const storage::RunRecord& run) {
  const auto found = run.config.find("sharding");
  return found == run.config.end() ? json() : *found;
}

/// The shards a run holds: its index, or those merged into it.
std::set<int> shards_in(const json& sharding) {
  if (sharding.contains("merged")) return sharding["merged"].get<std::set<int>>();
  return {sharding.value("index", 0)};
}

/// One run of the source as read, checked, before the target is touched.
struct SourceRun {
  storage::RunRecord run;
  storage::ScenarioRecord scenario;
  std::vector<storage::EpisodeRecord> episodes;  ///< whole, with their series
};

/// Reads every run of the source with its scenario and episodes, each value checked as the API would.
std::vector<SourceRun> read_source(storage::ForeignDatabase& source, const RunCheck& check_run) {
  storage::Store& store = source.store();
  const std::string& name = source.name();
  std::vector<SourceRun> runs;
  for (storage::RunRecord& run : store.all_runs()) {
    check_imported_run(run, name);
    if (run.status != "finished") {
      throw core::Error(core::ErrorCode::conflict, name + ": run " + run.id + " cannot be merged: it is " + run.status +
                                                       ", not finished: run that part again (into a new database) and merge that",
                        {{"run", run.id}, {"source", name}});
    }
    std::optional<storage::ScenarioRecord> scenario = store.scenario(run.scenario_id);
    if (!scenario) throw core::Error(core::ErrorCode::bad_request, name + ": run " + run.id + " names a scenario the database does not hold");
    check_imported_scenario(*scenario, name);
    if (check_run) {
      try {
        check_run(*scenario, run);
      } catch (const core::Error& e) {
        if (e.code() != core::ErrorCode::bad_request) throw;
        json details = e.details();
        details["run"] = run.id;
        throw core::Error(core::ErrorCode::bad_request, name + ": run " + run.id + "'s config is not one the API would take: " + e.what(), details);
      }
    }
    SourceRun read{std::move(run), std::move(*scenario), {}};
    std::set<std::uint64_t> seeds;
    for (const std::string& id : store.episode_ids_of_run(read.run.id)) {
      std::optional<storage::EpisodeRecord> episode = store.episode(id);
      if (!episode) throw core::Error(core::ErrorCode::bad_request, name + ": episode " + id + " vanished while reading");
      episode->series = store.series(id);
      check_imported_episode(*episode, read.run, name);
      if (!seeds.insert(episode->seed).second) throw core::Error(core::ErrorCode::bad_request, name + ": run " + read.run.id + " has two episodes of one seed");
      read.episodes.push_back(std::move(*episode));
    }
    runs.push_back(std::move(read));
  }
  return runs;
}

/// What is planned for one run of the source: the run as it will be in the target, and the source's
/// episodes to copy.
struct Plan {
  storage::RunRecord run;
  std::optional<storage::ScenarioRecord> scenario;  ///< to store, when the target lacks it
  std::vector<storage::EpisodeRecord> episodes;
  MergedRun merged;
  bool changed = true;  ///< false when the target has the run as it will be: nothing to write
};

class Merger {
 public:
  Merger(storage::Store& target, std::string source_name, std::string target_name, std::optional<std::string> owner)
      : target_(target), source_name_(std::move(source_name)), target_name_(std::move(target_name)), owner_(std::move(owner)) {
    if (owner_) id_key_ = target_.secret("import_ids");
  }

  Plan plan(SourceRun read) {
    Plan plan;
    plan.merged.source_id = read.run.id;
    if (owner_) read.run.id = id_for_owner(read.run.id);
    plan.merged.id = read.run.id;
    if (read.run.id != plan.merged.source_id) {
      // Its episodes' ids are another owner's too: this owner's get ids of their own in the same way.
      for (storage::EpisodeRecord& episode : read.episodes) episode.id = owned_id('e', episode.id);
    }
    place_scenario(read, plan);
    const std::optional<storage::RunRecord> existing = target_.run(read.run.id);
    std::map<std::uint64_t, storage::EpisodeRecord> there;
    if (existing) {
      if (owner_ && existing->owner != *owner_) refuse(read.run, "its id is held by another owner in " + target_name_);
      check_same(read.run, *existing);
      for (storage::EpisodeRecord& episode : target_.episodes_of_run(read.run.id)) there.emplace(episode.seed, std::move(episode));
    }
    plan.run = existing ? joined(*existing, read.run) : as_merged(read.run);
    for (storage::EpisodeRecord& episode : read.episodes) {
      const auto found = there.find(episode.seed);
      if (found == there.end()) {
        if (target_.has_episode(episode.id)) refuse(read.run, "an episode of it has an id " + target_name_ + " holds for another run");
        episode.run_id = plan.run.id;
        episode.scenario_id = plan.run.scenario_id;
        plan.episodes.push_back(std::move(episode));
        continue;
      }
      if (found->second.state_hash != episode.state_hash || found->second.status != episode.status) {
        refuse(read.run, "seed " + std::to_string(episode.seed) + " ended " + episode.status + " with state " + text_of(episode.state_hash) + " in " +
                             source_name_ + (owner_ ? ", otherwise in " + target_name_
                                                    : ", " + found->second.status + " with state " + text_of(found->second.state_hash) + " in " + target_name_));
      }
      ++plan.merged.present;
    }
    plan.merged.added = static_cast<int>(plan.episodes.size());
    plan.changed = !existing || !plan.episodes.empty() || plan.run.config != existing->config || plan.run.finished_at != existing->finished_at;
    return plan;
  }

  void write(const std::vector<Plan>& plans) {
    storage::Store::Batch batch(target_);
    for (const Plan& plan : plans) {
      if (!plan.changed) continue;
      if (plan.scenario) batch.put_scenario_if_missing(*plan.scenario);
      batch.put_run(plan.run);
      for (const storage::EpisodeRecord& episode : plan.episodes) batch.write_episode(episode);
    }
    batch.commit();
  }

 private:
  [[noreturn]] void refuse(const storage::RunRecord& run, const std::string& why) const {
    throw core::Error(core::ErrorCode::conflict, source_name_ + ": run " + run.id + (run.name.empty() ? "" : " (" + run.name + ")") + " cannot be merged: " + why,
                      {{"run", run.id}, {"source", source_name_}, {"target", target_name_}});
  }

  /// An importer's run: its own id, unless another owner holds that id; then one derived from the
  /// owner and the id, the same for every shard of the run this owner imports, and keyed with the
  /// target's secret so that no one can take it in advance.
  std::string id_for_owner(const std::string& id) const {
    const std::optional<storage::RunRecord> existing = target_.run(id);
    if (!existing || existing->owner == *owner_) return id;
    return owned_id('r', id);
  }

  /// The id of this owner's copy of a record of `id`.
  std::string owned_id(char prefix, const std::string& id) const {
    return prefix + core::sha256_hex(id_key_ + '\0' + *owner_ + '\0' + id).substr(0, 32);
  }

  /// Where the run's scenario is in the target: a content-addressed one at its id (the same content
  /// wherever it is); an upload at its id when the target lacks it or has it with the same content for
  /// this owner, else at a new id of its own.
  void place_scenario(SourceRun& read, Plan& plan) const {
    storage::ScenarioRecord scenario = std::move(read.scenario);
    scenario.summary.clear();  // recomputed from the source when listed: never taken from the file
    const std::optional<storage::ScenarioRecord> there = target_.scenario(scenario.id, false);
    if (is_content_addressed(scenario.id)) {
      scenario.owner.clear();  // a snapshot of content, shared as hrisim's own are
      if (!there) plan.scenario = std::move(scenario);
      return;
    }
    if (owner_) scenario.owner = *owner_;
    if (there && there->sha256 == scenario.sha256 && there->owner == scenario.owner) return;
    if (there) {
      scenario.id = core::unguessable_id('u');
      read.run.scenario_id = scenario.id;
    }
    plan.scenario = std::move(scenario);
  }

  /// The shards and the run of the same id must be one run: the same scenario content, hrisim, controller
  /// and split (and owner, for an import).
  void check_same(const storage::RunRecord& run, const storage::RunRecord& existing) const {
    const auto differs = [&](const std::string& what, const json& here, const json& there) {
      if (here == there) return;
      // An importer learns nothing of the target's run but that it differs.
      refuse(run, "its " + what + " is " + text_of(here) + " in " + source_name_ + (owner_ ? ", another in " + target_name_ : " but " + text_of(there) + " in " + target_name_));
    };
    differs("scenario's content (sha256)", run.config.value("scenario_sha256", json()), existing.config.value("scenario_sha256", json()));
    differs("hrisim version", run.config.value("hrisim_version", json()), existing.config.value("hrisim_version", json()));
    differs("controller", run.config.value("controller", json()), existing.config.value("controller", json()));
    differs("controller type", run.controller, existing.controller);
    const json sharding = sharding_of(run), existing_sharding = sharding_of(existing);
    const auto of = [](const json& object, const char* key) { return object.is_object() ? object.value(key, json()) : json(); };
    differs("shard count", of(sharding, "count"), of(existing_sharding, "count"));
    differs("whole seed list", of(sharding, "of_seeds"), of(existing_sharding, "of_seeds"));
    differs("gates", run.config.value("gates", json()), existing.config.value("gates", json()));
  }

  /// A shard's run as the first of its run in a merged database: `merged` lists the shards in it.
  storage::RunRecord as_merged(storage::RunRecord run) const {
    if (owner_) run.owner = *owner_;
    json sharding = sharding_of(run);
    if (sharding.is_null()) return run;
    sharding["merged"] = shards_in(sharding);
    sharding.erase("index");
    run.config["sharding"] = sharding;
    return run;
  }

  /// The run in the target with the source's seeds joined: in the whole run's order for shards, else
  /// the target's then the source's new ones.
  static storage::RunRecord joined(storage::RunRecord existing, const storage::RunRecord& run) {
    std::vector<std::uint64_t> here = run.config.value("seeds", std::vector<std::uint64_t>{});
    std::vector<std::uint64_t> there = existing.config.value("seeds", std::vector<std::uint64_t>{});
    const std::set<std::uint64_t> both = [&] {
      std::set<std::uint64_t> seeds(here.begin(), here.end());
      seeds.insert(there.begin(), there.end());
      return seeds;
    }();
    std::vector<std::uint64_t> seeds;
    json sharding = sharding_of(existing);
    if (!sharding.is_null()) {
      for (const std::uint64_t seed : sharding["of_seeds"].get<std::vector<std::uint64_t>>()) {
        if (both.contains(seed)) seeds.push_back(seed);
      }
      std::set<int> merged = shards_in(sharding);
      const std::set<int> added = shards_in(sharding_of(run));
      merged.insert(added.begin(), added.end());
      sharding["merged"] = merged;
      sharding.erase("index");
      existing.config["sharding"] = sharding;
    } else {
      seeds = there;
      for (const std::uint64_t seed : here) {
        if (std::find(there.begin(), there.end(), seed) == there.end()) seeds.push_back(seed);
      }
    }
    existing.config["seeds"] = seeds;
    if (run.finished_at && (!existing.finished_at || *run.finished_at > *existing.finished_at)) existing.finished_at = run.finished_at;
    return existing;
  }

  storage::Store& target_;
  std::string source_name_, target_name_;
  std::optional<std::string> owner_;
  std::string id_key_;  ///< the target's secret for derived ids
};

}  // namespace

std::vector<MergedRun> merge_database(storage::Store& target, storage::ForeignDatabase& source, const std::string& target_name,
                                      const std::optional<std::string>& owner, const RunCheck& check_run) {
  std::vector<SourceRun> read;
  try {
    read = read_source(source, check_run);
  } catch (const core::Error& e) {
    // The store's own refusals (JSON nested too deep, work spent) do not know whose file it is; and
    // what SQLite cannot read in the private copy (a file damaged where quick_check does not look:
    // fuzz_import found one whose copy lacked a table) is the file's fault too, not the server's.
    const std::string message = e.what();
    if (e.code() == core::ErrorCode::storage) throw core::Error(core::ErrorCode::bad_request, source.name() + " cannot be read: " + message);
    if (e.code() != core::ErrorCode::bad_request || message.starts_with(source.name())) throw;
    throw core::Error(core::ErrorCode::bad_request, source.name() + ": " + message, e.details());
  }
  Merger merger(target, source.name(), target_name, owner);
  std::vector<Plan> plans;
  for (SourceRun& run : read) plans.push_back(merger.plan(std::move(run)));
  merger.write(plans);
  std::vector<MergedRun> merged;
  for (const Plan& plan : plans) merged.push_back(plan.merged);
  return merged;
}

}  // namespace hrisim::runs
