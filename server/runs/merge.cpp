#include "runs/merge.hpp"

#include <algorithm>
#include <map>
#include <set>

#include "core/error.hpp"

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

/// What is planned for one run of the source: the run as it will be in the target, and the source's
/// episodes to copy.
struct Plan {
  storage::RunRecord run;
  std::vector<std::string> episodes;
  MergedRun merged;
  bool changed = true;  ///< false when the target has the run as it will be: nothing to write
};

class Merger {
 public:
  Merger(storage::Store& target, storage::Store& source, std::string source_name, std::string target_name, std::optional<std::string> owner)
      : target_(target), source_(source), source_name_(std::move(source_name)), target_name_(std::move(target_name)), owner_(std::move(owner)) {}

  Plan plan(const storage::RunRecord& run) {
    if (run.status != "finished") {
      refuse(run, "it is " + run.status + ", not finished: run that part again (into a new database) and merge that");
    }
    Plan plan;
    plan.merged.id = run.id;
    const std::optional<storage::RunRecord> existing = target_.run(run.id);
    std::map<std::uint64_t, storage::EpisodeRecord> there;
    if (existing) {
      check_same(run, *existing);
      for (storage::EpisodeRecord& episode : target_.episodes_of_run(run.id)) there.emplace(episode.seed, std::move(episode));
    }
    for (const storage::EpisodeRecord& episode : source_.episodes_of_run(run.id)) {
      const auto found = there.find(episode.seed);
      if (found == there.end()) {
        plan.episodes.push_back(episode.id);
        continue;
      }
      if (found->second.state_hash != episode.state_hash || found->second.status != episode.status) {
        refuse(run, "seed " + std::to_string(episode.seed) + " ended " + episode.status + " with state " + text_of(episode.state_hash) + " in " +
                        source_name_ + ", " + found->second.status + " with state " + text_of(found->second.state_hash) + " in " + target_name_);
      }
      ++plan.merged.present;
    }
    plan.merged.added = static_cast<int>(plan.episodes.size());
    plan.run = existing ? joined(*existing, run) : as_merged(run);
    plan.changed = !existing || !plan.episodes.empty() || plan.run.config != existing->config || plan.run.finished_at != existing->finished_at;
    return plan;
  }

  void write(const std::vector<Plan>& plans) {
    storage::Store::Batch batch(target_);
    std::set<std::string> scenarios;
    for (const Plan& plan : plans) {
      if (!plan.changed) continue;
      if (scenarios.insert(plan.run.scenario_id).second) {
        if (const auto scenario = source_.scenario(plan.run.scenario_id)) batch.put_scenario_if_missing(*scenario);
      }
      batch.put_run(plan.run);
      for (const std::string& id : plan.episodes) {
        std::optional<storage::EpisodeRecord> episode = source_.episode(id);
        if (!episode) throw core::Error(core::ErrorCode::internal, source_name_ + ": episode " + id + " vanished while merging");
        episode->series = source_.series(id);
        batch.write_episode(*episode);
      }
    }
    batch.commit();
  }

 private:
  [[noreturn]] void refuse(const storage::RunRecord& run, const std::string& why) const {
    throw core::Error(core::ErrorCode::conflict, source_name_ + ": run " + run.id + (run.name.empty() ? "" : " (" + run.name + ")") + " cannot be merged: " + why,
                      {{"run", run.id}, {"source", source_name_}, {"target", target_name_}});
  }

  /// The shards and the run of the same id must be one run: the same scenario content, hrisim, controller
  /// and split (and owner, for an import).
  void check_same(const storage::RunRecord& run, const storage::RunRecord& existing) const {
    const auto differs = [&](const std::string& what, const json& here, const json& there) {
      if (here == there) return;
      refuse(run, "its " + what + " is " + text_of(here) + " in " + source_name_ + " but " + text_of(there) + " in " + target_name_);
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
    if (owner_ && existing.owner != *owner_) refuse(run, "a run of that id belongs to another owner in " + target_name_);
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
  storage::Store& source_;
  std::string source_name_, target_name_;
  std::optional<std::string> owner_;
};

}  // namespace

std::vector<MergedRun> merge_database(storage::Store& target, storage::Store& source, const std::string& source_name,
                                      const std::string& target_name, const std::optional<std::string>& owner) {
  Merger merger(target, source, source_name, target_name, owner);
  std::vector<Plan> plans;
  for (const storage::RunRecord& run : source.all_runs()) plans.push_back(merger.plan(run));
  merger.write(plans);
  std::vector<MergedRun> merged;
  for (const Plan& plan : plans) merged.push_back(plan.merged);
  return merged;
}

}  // namespace hrisim::runs
