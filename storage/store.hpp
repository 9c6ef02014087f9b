#pragma once
// The episode store: scenarios with their source, runs, and episodes with metrics, events and sampled
// trajectories, in one SQLite file. Thread-safe; an episode is written in one transaction, so a crash
// loses at most the episodes in flight, never a committed one.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "storage/migrations.hpp"

namespace hrisim::storage {

class Database;
class Transaction;

struct ScenarioRecord {
  std::string id;
  std::string name;
  std::string format;  ///< "json", "imhus_xml", "pedsim_xml" or "hunav_yaml"
  std::string source;  ///< the uploaded text, byte for byte
  std::string sha256;  ///< filled by the store from source
  std::string created_at;  ///< RFC 3339 UTC, filled by the store
  std::string summary;  ///< JSON of what a list shows of it; empty when not stored (older uploads)
  std::string owner;    ///< name of the token that uploaded it; empty without owners
  /// Files uploaded alongside it, by path relative to the scenario; read only with its source.
  std::map<std::string, std::string> files;
};

/// What is wrong with a path a scenario names one of its files by, or empty when it is fine: relative,
/// at most 255 bytes, of segments made of letters, digits, '.', '_' and '-', none of them "." or "..",
/// so that a scenario's files are written below its folder and nowhere else.
std::string scenario_file_path_problem(const std::string& path);

/// The sha256 that names a scenario's content: of its source alone when it has no files, else of the
/// source followed by each file (in path order) as its path, its size and its bytes, NUL-separated.
std::string scenario_sha256(const std::string& source, const std::map<std::string, std::string>& files);

struct RunRecord {
  std::string id;
  std::string scenario_id;
  std::string controller;
  nlohmann::json config = nlohmann::json::object();  ///< seeds, gates, options
  std::string status;  ///< queued, running, finished, failed, cancelled, interrupted
  std::string created_at;
  std::optional<std::string> finished_at;
  std::string owner;  ///< name of the token that started it; empty without owners
  std::string name;   ///< given by its user; may be empty
  std::vector<std::string> tags;
  std::string notes;
};

/// A run's aggregate statistic compared with a number: what a list keeps (a gate's form).
struct RunFilter {
  std::string metric, statistic;
  std::string op;  ///< ==, !=, <, <=, >, >=
  double threshold = 0.0;
};

/// Which runs a list gives, in which order.
struct RunQuery {
  int limit = 20;
  std::string after_id;     ///< newest first: the page after this run
  std::int64_t offset = 0;  ///< sorted by a metric: runs to skip
  std::string status;
  std::string scenario_id;  ///< the stored record's id or the catalogue id in config.scenario
  std::optional<std::string> owner;
  std::string text;  ///< in the name, notes, tags, scenario or controller, any case
  std::string tag;   ///< one of its tags, exactly
  /// Sorted by this metric's statistic (runs without it last), else newest first.
  std::optional<std::pair<std::string, std::string>> sort;
  bool descending = true;
  std::vector<RunFilter> filters;  ///< every one holds (a run without the statistic is left out)
};

/// One metric of an episode: a finite value, or no value and the reason why.
struct MetricValue {
  std::string key;
  std::optional<double> value;
  std::optional<std::string> null_reason;
};

struct EventRecord {
  std::int64_t tick = 0;
  double time = 0.0;  ///< seconds of simulation time
  std::string kind;   ///< e.g. "collision", "request", "step_boundary"
  std::string subject;
  nlohmann::json data = nlohmann::json::object();
};

struct TrajectorySample {
  std::string agent_id;
  std::int64_t tick = 0;
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;
};

/// A per-step series of an episode, sampled every `stride` ticks from `first_tick`.
struct SeriesRecord {
  std::string name;
  std::int64_t first_tick = 0;
  std::int64_t stride = 1;
  std::vector<std::optional<double>> values;  ///< empty where a step has no value
};

struct EpisodeRecord {
  std::string id;
  std::optional<std::string> run_id;  ///< empty for an episode of a live session
  std::string scenario_id;
  std::uint64_t seed = 0;
  std::string controller;
  std::string status;
  std::string termination_reason;
  std::int64_t ticks = 0;
  double sim_time = 0.0;
  std::string created_at;
  /// The final state's hash (sim::Session::state_hash, 16 hex digits); empty when not known.
  std::string state_hash;
  std::vector<MetricValue> metrics;
  std::vector<EventRecord> events;  ///< in order of occurrence
  std::vector<TrajectorySample> trajectory;
  std::vector<SeriesRecord> series;
};

/// Removes an SQLite database file with its write-ahead log and shared-memory index, if there.
void remove_database(const std::filesystem::path& path);

/// Counts of what is stored, for health and tests.
struct StoreCounts {
  std::int64_t scenarios = 0, runs = 0, episodes = 0, metric_values = 0, events = 0, trajectory_samples = 0;
};

class Store {
 public:
  /// Opens or creates the database at path and applies `migrations` (the shipped ones by default).
  explicit Store(const std::filesystem::path& path,
                 std::span<const Migration> migrations = schema_migrations());
  /// A store over an open connection (a foreign database's private copy: see storage/foreign.hpp),
  /// migrated as above.
  Store(std::unique_ptr<Database> db, std::span<const Migration> migrations);
  ~Store();
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;

  /// Schema version of the open file (PRAGMA user_version).
  int schema_version();
  /// Result of PRAGMA integrity_check: "ok" when the file is sound.
  std::string integrity_check();
  /// Cheap liveness probe of the connection; throws core::Error when the database does not answer, or
  /// when the last episode could not be written (a full disk or database) and none has been since.
  void ping();
  /// Caps the file at about `bytes` (SQLite's max_page_count): writes beyond fail as on a full disk.
  void limit_size(std::uint64_t bytes);
  StoreCounts counts();

  /// Stores a scenario and its files; computes its sha256 (of the source, and of the files when there
  /// are any: see scenario_sha256) and created_at. Returns the stored record.
  ScenarioRecord put_scenario(ScenarioRecord scenario);
  /// Stores it as put_scenario does unless a scenario with its id is there: one step, so two callers
  /// storing the same scenario at once store it once.
  void put_scenario_if_missing(ScenarioRecord scenario);
  /// A scenario; its source and files left empty unless `with_source` (they may be megabytes).
  std::optional<ScenarioRecord> scenario(const std::string& id, bool with_source = true);
  /// The id of a listed or unlisted scenario of `owner` whose id starts with `id_prefix`, of this
  /// format and content (scenario_sha256); none when there is none.
  std::optional<std::string> scenario_with_content(const std::string& sha256, const std::string& format, const std::string& owner,
                                                   const std::string& id_prefix);
  /// Lists or unlists a scenario (see delete_scenario).
  void set_scenario_listed(const std::string& id, bool listed);
  /// Deletes a scenario and its files when no run or episode refers to it (true); otherwise only
  /// unlists it (false), so that what ran it still finds it by id.
  bool delete_scenario(const std::string& id);
  /// Listed scenarios ordered by id, at most `limit`, starting after `after_id` (paging cursor), only
  /// ids starting with `id_prefix` when given, only `owner`'s when given; without their sources.
  std::vector<ScenarioRecord> scenarios(int limit, const std::string& after_id = "", const std::string& id_prefix = "",
                                        const std::optional<std::string>& owner = std::nullopt);

  RunRecord put_run(RunRecord run);
  std::optional<RunRecord> run(const std::string& id);
  /// Sets a run's status; a terminal status also stamps finished_at.
  void set_run_status(const std::string& id, const std::string& status);
  /// Runs newest first, optionally only those with this status and/or scenario (the stored record's
  /// id or the catalogue id in config.scenario); at most `limit`, after
  /// the run with id `after_id` (paging cursor).
  std::vector<RunRecord> runs(int limit, const std::string& after_id = "", const std::string& status = "",
                              const std::string& scenario_id = "", const std::optional<std::string>& owner = std::nullopt);
  /// The runs a query asks for. Sorting and filtering by a metric read the stored summaries.
  std::vector<RunRecord> runs(const RunQuery& query);
  /// Sets what the user gives a run: its name, tags and notes.
  void set_run_labels(const std::string& id, const std::string& name, const std::vector<std::string>& tags, const std::string& notes);
  /// Keeps an ended run's summary: {metric: {statistic: value or null}}.
  void set_run_summary(const std::string& id, const nlohmann::json& summary);
  /// Ended runs without a summary yet (stored before summaries were, or by another process).
  std::vector<RunRecord> ended_runs_without_summary();
  /// Marks 'interrupted' every queued or running run whose process has ended (a server or `hrisim run`
  /// that was killed): each run records the process that computes it, so runs of a process still
  /// alive — another one sharing the file — are left alone. Returns how many.
  int interrupt_abandoned_runs();
  /// Stores the summary of a scenario stored without one.
  void set_scenario_summary(const std::string& id, const std::string& summary);

  /// Writes the episode with all its metrics, events and trajectory in one transaction.
  void write_episode(const EpisodeRecord& episode);
  /// The episode with everything stored for it but its series.
  std::optional<EpisodeRecord> episode(const std::string& id);
  /// Whether an episode of this id is stored.
  bool has_episode(const std::string& id);
  /// An episode's series; only the one named `name` when given.
  std::vector<SeriesRecord> series(const std::string& episode_id, const std::string& name = "");
  /// Ids of a run's episodes in the order they were written.
  std::vector<std::string> episode_ids_of_run(const std::string& run_id);
  /// A run's episodes in the order of their seeds, with their metrics but without events and
  /// trajectory: the same order however many threads, processes or machines ran them, so that
  /// aggregates over them come out the same to the bit.
  std::vector<EpisodeRecord> episodes_of_run(const std::string& run_id);
  /// Every run, oldest first.
  std::vector<RunRecord> all_runs();

  /// Runs and episodes copied from another database (a merge of shards, an import), written in one
  /// transaction that holds the store while the batch lives: nothing is kept unless commit() is called.
  class Batch {
   public:
    explicit Batch(Store& store);
    ~Batch();
    Batch(const Batch&) = delete;
    Batch& operator=(const Batch&) = delete;
    /// Stores the scenario (with its files) unless one with its id is there.
    void put_scenario_if_missing(const ScenarioRecord& scenario);
    /// Inserts the run as it is (its created_at and finished_at kept) or, when there is one with its
    /// id, sets that one's config, status and finished_at, and drops its summary (a list computes it again).
    void put_run(const RunRecord& run);
    /// Writes an episode as Store::write_episode does.
    void write_episode(const EpisodeRecord& episode);
    void commit();

   private:
    Store& store_;
    std::unique_lock<std::mutex> lock_;
    std::unique_ptr<Transaction> transaction_;
  };

  /// The secret of this database called `name`: 32 random hex digits, made when first asked for and
  /// kept with the database (never in what it exports: a merge or an import copies runs, not secrets).
  std::string secret(const std::string& name);

  /// Version of the SQLite library in use, e.g. "3.40.1".
  static std::string sqlite_version();

 private:
  std::mutex mutex_;
  std::unique_ptr<Database> db_;
  std::string write_failure_;  ///< why the last episode could not be written; empty once one has been
  void write_episode_locked(const EpisodeRecord& episode);
  /// put_scenario with the lock held.
  ScenarioRecord insert_scenario(ScenarioRecord scenario);
  /// The episode's rows, inside a transaction the caller holds.
  void insert_episode_rows(const EpisodeRecord& episode);
};

}  // namespace hrisim::storage
