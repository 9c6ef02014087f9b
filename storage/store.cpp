#include "storage/store.hpp"

#include <sqlite3.h>

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <fstream>
#include <set>
#include <sstream>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/bounded_json.hpp"
#include "core/error.hpp"
#include "core/random.hpp"
#include "core/sha256.hpp"
#include "core/text.hpp"
#include "storage/sqlite.hpp"

namespace hrisim::storage {
namespace {

// SQLite integers are signed 64-bit; seeds are unsigned, so they are stored with their bits unchanged.
std::int64_t seed_to_column(std::uint64_t seed) { return std::bit_cast<std::int64_t>(seed); }
std::uint64_t seed_from_column(std::int64_t value) { return std::bit_cast<std::uint64_t>(value); }

bool is_terminal_run_status(const std::string& status) {
  return status == "finished" || status == "failed" || status == "cancelled" || status == "interrupted";
}

ScenarioRecord read_scenario(const Statement& row) {
  return {row.text(0), row.text(1), row.text(2), row.text(3), row.text(4), row.text(5), row.optional_text(6).value_or(""), row.text(7), {}};
}

constexpr std::string_view kScenarioColumns = "id, name, format, source, sha256, created_at, summary, owner";
constexpr std::string_view kScenarioColumnsWithoutSource = "id, name, format, '', sha256, created_at, summary, owner";

constexpr std::string_view kRunColumns = "id, scenario_id, controller, config, status, created_at, finished_at, owner, name, tags, notes";

RunRecord read_run(const Statement& row) {
  // JSON read back is bounded as a request's is: a database may have come from elsewhere.
  const nlohmann::json tags = core::parse_bounded_json(row.text(9), "a run's tags");
  if (!tags.is_array() || !std::all_of(tags.begin(), tags.end(), [](const nlohmann::json& tag) { return tag.is_string(); })) {
    throw core::Error(core::ErrorCode::bad_request, "a run's tags are not a list of words");
  }
  return {row.text(0), row.text(1), row.text(2), core::parse_bounded_json(row.text(3), "a run's config"), row.text(4), row.text(5),
          row.optional_text(6), row.text(7), row.text(8), tags.get<std::vector<std::string>>(), row.text(10)};
}

/// The SQL path of a metric's statistic in a run's summary (names are checked against the metric
/// definitions before they get here; quoted all the same).
std::string summary_path(const std::string& metric, const std::string& statistic) {
  const auto quoted = [](const std::string& name) {
    std::string out = "\"";
    for (const char c : name) {
      if (c == '"' || c == '\\') out.push_back('\\');
      out.push_back(c);
    }
    return out + "\"";
  };
  return "$." + quoted(metric) + "." + quoted(statistic);
}

/// What tells this process apart from any other, even one that later gets the same pid: the machine's
/// boot id and the process's start time in clock ticks since boot (field 22 of /proc/PID/stat).
std::string process_identity(long pid) {
  std::ifstream boot("/proc/sys/kernel/random/boot_id");
  std::string boot_id;
  std::getline(boot, boot_id);
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return "";
  // The command name (field 2) may hold spaces and parentheses: count fields after its last ')'.
  std::istringstream fields(line.substr(line.rfind(')') + 2));
  std::string state, field;
  fields >> state;
  if (state == "Z" || state == "X") return "";  // killed, not yet reaped by its parent: gone all the same
  for (int index = 4; index <= 22 && fields >> field; ++index) {
  }
  return boot_id + "/" + field;
}

constexpr std::string_view kEpisodeColumns =
    "id, run_id, scenario_id, seed, controller, status, termination_reason, ticks, sim_time, created_at, state_hash";

EpisodeRecord read_episode(const Statement& row) {
  EpisodeRecord episode;
  episode.id = row.text(0);
  episode.run_id = row.optional_text(1);
  episode.scenario_id = row.text(2);
  episode.seed = seed_from_column(row.integer(3));
  episode.controller = row.text(4);
  episode.status = row.text(5);
  episode.termination_reason = row.text(6);
  episode.ticks = row.integer(7);
  episode.sim_time = row.real(8);
  episode.created_at = row.text(9);
  episode.state_hash = row.optional_text(10).value_or("");
  return episode;
}

std::vector<MetricValue> read_metrics(Database& db, const std::string& episode_id) {
  Statement select = db.prepare("SELECT key, value, null_reason FROM metric_values WHERE episode_id = ?1 ORDER BY key");
  select.bind(1, episode_id);
  std::vector<MetricValue> metrics;
  while (select.step()) metrics.push_back({select.text(0), select.optional_real(1), select.optional_text(2)});
  return metrics;
}

}  // namespace

std::string scenario_file_path_problem(const std::string& path) {
  if (path.empty() || path.size() > 255) return "a file's path is 1 to 255 bytes";
  std::size_t start = 0;
  while (start <= path.size()) {
    const std::size_t end = std::min(path.find('/', start), path.size());
    const std::string_view segment(path.data() + start, end - start);
    if (segment.empty() || segment == "." || segment == "..") {
      return "a file's path is relative, without empty, '.' or '..' segments: it names a file next to the scenario or below it";
    }
    for (const char c : segment) {
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-') {
        return "a file's path is made of letters, digits, '.', '_', '-' and '/'";
      }
    }
    start = end + 1;
  }
  return "";
}

Store::Store(const std::filesystem::path& path, std::span<const Migration> migrations) : Store(std::make_unique<Database>(path), migrations) {}

Store::Store(std::unique_ptr<Database> db, std::span<const Migration> migrations) : db_(std::move(db)) { migrate(*db_, migrations); }

Store::~Store() = default;

int Store::schema_version() {
  std::lock_guard lock(mutex_);
  return static_cast<int>(db_->scalar_integer("PRAGMA user_version"));
}

std::string Store::integrity_check() {
  std::lock_guard lock(mutex_);
  Statement statement = db_->prepare("PRAGMA integrity_check");
  std::string result;
  while (statement.step()) {
    if (!result.empty()) result += "\n";
    result += statement.text(0);
  }
  return result;
}

void Store::ping() {
  std::lock_guard lock(mutex_);
  db_->scalar_integer("SELECT count(*) FROM sqlite_schema");
  if (!write_failure_.empty()) throw core::Error(core::ErrorCode::storage, "writes fail: " + write_failure_);
}

void Store::limit_size(std::uint64_t bytes) {
  std::lock_guard lock(mutex_);
  const auto page = static_cast<std::uint64_t>(db_->scalar_integer("PRAGMA page_size"));
  db_->exec("PRAGMA max_page_count = " + std::to_string(std::max<std::uint64_t>(1, bytes / page)));
}

StoreCounts Store::counts() {
  std::lock_guard lock(mutex_);
  Statement statement = db_->prepare(
      "SELECT (SELECT count(*) FROM scenarios), (SELECT count(*) FROM runs), (SELECT count(*) FROM episodes),"
      " (SELECT count(*) FROM metric_values), (SELECT count(*) FROM events),"
      " (SELECT count(*) FROM trajectory_samples)");
  statement.step();
  return {statement.integer(0), statement.integer(1), statement.integer(2),
          statement.integer(3), statement.integer(4), statement.integer(5)};
}

std::string scenario_sha256(const std::string& source, const std::map<std::string, std::string>& files) {
  if (files.empty()) return core::sha256_hex(source);
  std::string content = source;
  for (const auto& [path, bytes] : files) {
    content.push_back('\0');
    content += path;
    content.push_back('\0');
    content += std::to_string(bytes.size());
    content.push_back('\0');
    content += bytes;
  }
  return core::sha256_hex(content);
}

ScenarioRecord Store::put_scenario(ScenarioRecord scenario) {
  std::lock_guard lock(mutex_);
  return insert_scenario(std::move(scenario));
}

void Store::put_scenario_if_missing(ScenarioRecord scenario) {
  std::lock_guard lock(mutex_);
  Statement exists = db_->prepare("SELECT 1 FROM scenarios WHERE id = ?1");
  exists.bind(1, scenario.id);
  if (!exists.step()) insert_scenario(std::move(scenario));
}

ScenarioRecord Store::insert_scenario(ScenarioRecord scenario) {
  scenario.sha256 = scenario_sha256(scenario.source, scenario.files);
  Transaction transaction(*db_);
  {
    Statement insert = db_->prepare(
        "INSERT INTO scenarios (id, name, format, source, sha256, summary, owner) VALUES (?1, ?2, ?3, ?4, ?5, nullif(?6, ''), ?7)"
        " RETURNING created_at");
    insert.bind(1, scenario.id).bind(2, scenario.name).bind(3, scenario.format).bind(4, scenario.source);
    insert.bind(5, scenario.sha256).bind(6, scenario.summary).bind(7, scenario.owner);
    insert.step();
    scenario.created_at = insert.text(0);
  }  // finished before the transaction commits
  for (const auto& [path, bytes] : scenario.files) {
    Statement file = db_->prepare("INSERT INTO scenario_files (scenario_id, path, content) VALUES (?1, ?2, ?3)");
    file.bind(1, scenario.id).bind(2, path).bind_blob(3, bytes);
    file.step();
  }
  transaction.commit();
  return scenario;
}

std::optional<ScenarioRecord> Store::scenario(const std::string& id, bool with_source) {
  std::lock_guard lock(mutex_);
  Statement select = db_->prepare("SELECT " + std::string(with_source ? kScenarioColumns : kScenarioColumnsWithoutSource) +
                                  " FROM scenarios WHERE id = ?1");
  select.bind(1, id);
  if (!select.step()) return std::nullopt;
  ScenarioRecord record = read_scenario(select);
  if (with_source) {
    Statement files = db_->prepare("SELECT path, content FROM scenario_files WHERE scenario_id = ?1");
    files.bind(1, id);
    while (files.step()) record.files.emplace(files.text(0), files.blob(1));
  }
  return record;
}

std::vector<ScenarioRecord> Store::scenarios(int limit, const std::string& after_id, const std::string& id_prefix,
                                             const std::optional<std::string>& owner) {
  std::lock_guard lock(mutex_);
  Statement select = db_->prepare("SELECT " + std::string(kScenarioColumnsWithoutSource) +
                                  " FROM scenarios WHERE id > ?1 AND substr(id, 1, length(?3)) = ?3 AND (?4 IS NULL OR owner = ?4) AND listed"
                                  " ORDER BY id LIMIT ?2");
  select.bind(1, after_id).bind(2, std::int64_t{limit}).bind(3, id_prefix);
  if (owner) select.bind(4, *owner);
  std::vector<ScenarioRecord> result;
  while (select.step()) result.push_back(read_scenario(select));
  return result;
}

std::optional<std::string> Store::scenario_with_content(const std::string& sha256, const std::string& format, const std::string& owner,
                                                        const std::string& id_prefix) {
  std::lock_guard lock(mutex_);
  Statement select = db_->prepare(
      "SELECT id FROM scenarios WHERE sha256 = ?1 AND format = ?2 AND owner = ?3 AND substr(id, 1, length(?4)) = ?4 ORDER BY rowid LIMIT 1");
  select.bind(1, sha256).bind(2, format).bind(3, owner).bind(4, id_prefix);
  if (!select.step()) return std::nullopt;
  return select.text(0);
}

void Store::set_scenario_listed(const std::string& id, bool listed) {
  std::lock_guard lock(mutex_);
  Statement update = db_->prepare("UPDATE scenarios SET listed = ?2 WHERE id = ?1");
  update.bind(1, id).bind(2, std::int64_t{listed});
  update.run();
}

bool Store::delete_scenario(const std::string& id) {
  std::lock_guard lock(mutex_);
  Transaction transaction(*db_);
  bool used = false;
  {
    Statement uses = db_->prepare(
        "SELECT EXISTS (SELECT 1 FROM runs WHERE scenario_id = ?1) OR EXISTS (SELECT 1 FROM episodes WHERE scenario_id = ?1)");
    uses.bind(1, id);
    uses.step();
    used = uses.integer(0) != 0;
  }
  Statement change = db_->prepare(used ? "UPDATE scenarios SET listed = 0 WHERE id = ?1" : "DELETE FROM scenarios WHERE id = ?1");
  change.bind(1, id);
  change.run();
  transaction.commit();
  return !used;
}

RunRecord Store::put_run(RunRecord run) {
  std::lock_guard lock(mutex_);
  Statement insert = db_->prepare(
      "INSERT INTO runs (id, scenario_id, controller, config, status, owner, process_id, process_identity, name, tags, notes)"
      " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11) RETURNING created_at");
  insert.bind(1, run.id).bind(2, run.scenario_id).bind(3, run.controller).bind(4, core::json_text(run.config));
  insert.bind(5, run.status).bind(6, run.owner).bind(7, std::int64_t{getpid()}).bind(8, process_identity(getpid()));
  insert.bind(9, run.name).bind(10, core::json_text(nlohmann::json(run.tags))).bind(11, run.notes);
  insert.step();
  run.created_at = insert.text(0);
  return run;
}

std::optional<RunRecord> Store::run(const std::string& id) {
  std::lock_guard lock(mutex_);
  Statement select = db_->prepare("SELECT " + std::string(kRunColumns) + " FROM runs WHERE id = ?1");
  select.bind(1, id);
  if (!select.step()) return std::nullopt;
  return read_run(select);
}

std::vector<RunRecord> Store::runs(int limit, const std::string& after_id, const std::string& status,
                                   const std::string& scenario_id, const std::optional<std::string>& owner) {
  std::lock_guard lock(mutex_);
  Statement select = db_->prepare(
      "SELECT " + std::string(kRunColumns) + " FROM runs"
      " WHERE (?1 = '' OR rowid < (SELECT rowid FROM runs WHERE id = ?1)) AND (?2 = '' OR status = ?2)"
      " AND (?3 = '' OR scenario_id = ?3 OR json_extract(config, '$.scenario') = ?3) AND (?5 IS NULL OR owner = ?5)"
      " ORDER BY rowid DESC LIMIT ?4");
  select.bind(1, after_id).bind(2, status).bind(3, scenario_id).bind(4, std::int64_t{limit});
  if (owner) select.bind(5, *owner);
  std::vector<RunRecord> list;
  while (select.step()) list.push_back(read_run(select));
  return list;
}

std::vector<RunRecord> Store::runs(const RunQuery& query) {
  static const std::set<std::string> kOperators{"==", "!=", "<", "<=", ">", ">="};
  std::string sql = "SELECT " + std::string(kRunColumns) +
                    " FROM runs WHERE (?1 = '' OR status = ?1)"
                    " AND (?2 = '' OR scenario_id = ?2 OR json_extract(config, '$.scenario') = ?2) AND (?3 IS NULL OR owner = ?3)"
                    " AND (?4 = '' OR instr(lower(name || ' ' || notes || ' ' || tags || ' ' || coalesce(json_extract(config, '$.scenario'), scenario_id) ||"
                    " ' ' || controller), lower(?4)) > 0)"
                    " AND (?5 = '' OR EXISTS (SELECT 1 FROM json_each(runs.tags) WHERE value = ?5))";
  int parameter = 6;
  for (const RunFilter& filter : query.filters) {
    if (!kOperators.contains(filter.op)) throw core::Error(core::ErrorCode::bad_request, "unknown comparison '" + filter.op + "'");
    const std::string op = filter.op == "==" ? "=" : filter.op;
    sql += " AND json_extract(summary, ?" + std::to_string(parameter) + ") " + op + " ?" + std::to_string(parameter + 1);
    parameter += 2;
  }
  const int limit_at = parameter, page_at = parameter + 1;
  if (query.sort) {
    const int sort_at = parameter + 2;
    sql += " ORDER BY json_extract(summary, ?" + std::to_string(sort_at) + ") IS NULL, json_extract(summary, ?" + std::to_string(sort_at) +
           ") " + (query.descending ? "DESC" : "ASC") + ", rowid DESC LIMIT ?" + std::to_string(limit_at) + " OFFSET ?" + std::to_string(page_at);
  } else {
    sql += " AND (?" + std::to_string(page_at) + " = '' OR rowid < (SELECT rowid FROM runs WHERE id = ?" + std::to_string(page_at) +
           ")) ORDER BY rowid DESC LIMIT ?" + std::to_string(limit_at);
  }
  std::lock_guard lock(mutex_);
  Statement select = db_->prepare(sql);
  select.bind(1, query.status).bind(2, query.scenario_id).bind(4, query.text).bind(5, query.tag);
  if (query.owner) select.bind(3, *query.owner);
  parameter = 6;
  for (const RunFilter& filter : query.filters) {
    select.bind(parameter, summary_path(filter.metric, filter.statistic)).bind(parameter + 1, filter.threshold);
    parameter += 2;
  }
  select.bind(limit_at, std::int64_t{query.limit});
  if (query.sort) {
    select.bind(page_at, query.offset).bind(parameter + 2, summary_path(query.sort->first, query.sort->second));
  } else {
    select.bind(page_at, query.after_id);
  }
  std::vector<RunRecord> list;
  while (select.step()) list.push_back(read_run(select));
  return list;
}

void Store::set_run_labels(const std::string& id, const std::string& name, const std::vector<std::string>& tags, const std::string& notes) {
  std::lock_guard lock(mutex_);
  Statement update = db_->prepare("UPDATE runs SET name = ?2, tags = ?3, notes = ?4 WHERE id = ?1");
  update.bind(1, id).bind(2, name).bind(3, core::json_text(nlohmann::json(tags))).bind(4, notes);
  update.run();
}

void Store::set_run_summary(const std::string& id, const nlohmann::json& summary) {
  std::lock_guard lock(mutex_);
  Statement update = db_->prepare("UPDATE runs SET summary = ?2 WHERE id = ?1");
  update.bind(1, id).bind(2, core::json_text(summary));
  update.run();
}

std::vector<RunRecord> Store::ended_runs_without_summary() {
  std::lock_guard lock(mutex_);
  Statement select = db_->prepare("SELECT " + std::string(kRunColumns) +
                                  " FROM runs WHERE summary IS NULL AND status IN ('finished', 'failed', 'cancelled', 'interrupted')");
  std::vector<RunRecord> list;
  while (select.step()) list.push_back(read_run(select));
  return list;
}

int Store::interrupt_abandoned_runs() {
  std::lock_guard lock(mutex_);
  std::vector<std::string> abandoned;
  {
    Statement select = db_->prepare("SELECT id, process_id, process_identity FROM runs WHERE status IN ('queued', 'running')");
    while (select.step()) {
      const auto pid = select.optional_text(1);
      const auto identity = select.optional_text(2);
      const bool alive = pid && identity && !identity->empty() && process_identity(std::stol(*pid)) == *identity;
      if (!alive) abandoned.push_back(select.text(0));
    }
  }
  for (const std::string& id : abandoned) {
    Statement update = db_->prepare(
        "UPDATE runs SET status = 'interrupted', finished_at = strftime('%Y-%m-%dT%H:%M:%fZ', 'now') WHERE id = ?1");
    update.bind(1, id);
    update.run();
  }
  return static_cast<int>(abandoned.size());
}

void Store::set_scenario_summary(const std::string& id, const std::string& summary) {
  std::lock_guard lock(mutex_);
  Statement update = db_->prepare("UPDATE scenarios SET summary = ?2 WHERE id = ?1 AND summary IS NULL");
  update.bind(1, id).bind(2, summary);
  update.run();
}

void Store::set_run_status(const std::string& id, const std::string& status) {
  std::lock_guard lock(mutex_);
  Statement update = db_->prepare(
      "UPDATE runs SET status = ?2,"
      " finished_at = CASE WHEN ?3 THEN strftime('%Y-%m-%dT%H:%M:%fZ', 'now') ELSE finished_at END"
      " WHERE id = ?1");
  update.bind(1, id).bind(2, status).bind(3, std::int64_t{is_terminal_run_status(status)});
  update.run();
  if (db_->scalar_integer("SELECT changes()") == 0) {
    throw core::Error(core::ErrorCode::not_found, "run " + id + " does not exist", {{"run_id", id}});
  }
}

void Store::write_episode(const EpisodeRecord& episode) {
  std::lock_guard lock(mutex_);
  try {
    write_episode_locked(episode);
    write_failure_.clear();
  } catch (const core::Error& e) {
    write_failure_ = e.what();
    throw;
  }
}

void Store::write_episode_locked(const EpisodeRecord& episode) {
  Transaction transaction(*db_);
  insert_episode_rows(episode);
  transaction.commit();
}

void Store::insert_episode_rows(const EpisodeRecord& episode) {
  Statement insert_episode = db_->prepare(
      "INSERT INTO episodes (id, run_id, scenario_id, seed, controller, status, termination_reason, ticks, sim_time, state_hash)"
      " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)");
  insert_episode.bind(1, episode.id).bind(2, episode.run_id).bind(3, episode.scenario_id);
  insert_episode.bind(4, seed_to_column(episode.seed)).bind(5, episode.controller).bind(6, episode.status);
  insert_episode.bind(7, episode.termination_reason).bind(8, episode.ticks).bind(9, episode.sim_time);
  insert_episode.bind(10, episode.state_hash.empty() ? std::nullopt : std::optional<std::string>(episode.state_hash));
  insert_episode.run();

  for (const MetricValue& metric : episode.metrics) {
    if (metric.value && !std::isfinite(*metric.value)) {
      throw core::Error(core::ErrorCode::bad_request,
                        "metric " + metric.key + " of episode " + episode.id +
                            " is not finite; store no value and a null_reason instead",
                        {{"episode_id", episode.id}, {"metric", metric.key}});
    }
  }
  Statement insert_metric =
      db_->prepare("INSERT INTO metric_values (episode_id, key, value, null_reason) VALUES (?1, ?2, ?3, ?4)");
  for (const MetricValue& metric : episode.metrics) {
    insert_metric.bind(1, episode.id).bind(2, metric.key).bind(3, metric.value).bind(4, metric.null_reason);
    insert_metric.run();
  }

  Statement insert_event = db_->prepare(
      "INSERT INTO events (episode_id, seq, tick, time, kind, subject, data) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)");
  std::int64_t seq = 0;
  for (const EventRecord& event : episode.events) {
    insert_event.bind(1, episode.id).bind(2, seq++).bind(3, event.tick).bind(4, event.time).bind(5, event.kind);
    insert_event.bind(6, event.subject).bind(7, core::json_text(event.data));
    insert_event.run();
  }

  Statement insert_sample = db_->prepare(
      "INSERT INTO trajectory_samples (episode_id, agent_id, tick, x, y, theta) VALUES (?1, ?2, ?3, ?4, ?5, ?6)");
  for (const TrajectorySample& sample : episode.trajectory) {
    insert_sample.bind(1, episode.id).bind(2, sample.agent_id).bind(3, sample.tick).bind(4, sample.x);
    insert_sample.bind(5, sample.y).bind(6, sample.theta);
    insert_sample.run();
  }
  Statement insert_series = db_->prepare(
      "INSERT INTO metric_series (episode_id, name, first_tick, stride, vals) VALUES (?1, ?2, ?3, ?4, ?5)");
  for (const SeriesRecord& series : episode.series) {
    static_assert(std::endian::native == std::endian::little, "series are stored as little-endian float64");
    std::string bytes(series.values.size() * sizeof(double), '\0');
    for (std::size_t i = 0; i < series.values.size(); ++i) {
      if (series.values[i] && !std::isfinite(*series.values[i])) {
        throw core::Error(core::ErrorCode::bad_request, "series " + series.name + " of episode " + episode.id + " holds a value that is not finite",
                          {{"episode_id", episode.id}, {"series", series.name}});
      }
      const double value = series.values[i].value_or(std::numeric_limits<double>::quiet_NaN());
      std::memcpy(bytes.data() + i * sizeof(double), &value, sizeof value);
    }
    insert_series.bind(1, episode.id).bind(2, series.name).bind(3, series.first_tick).bind(4, series.stride).bind_blob(5, bytes);
    insert_series.run();
  }
}

std::vector<SeriesRecord> Store::series(const std::string& episode_id, const std::string& name) {
  std::lock_guard lock(mutex_);
  Statement select = db_->prepare(
      "SELECT name, first_tick, stride, vals FROM metric_series WHERE episode_id = ?1 AND (?2 = '' OR name = ?2) ORDER BY name");
  select.bind(1, episode_id).bind(2, name);
  std::vector<SeriesRecord> list;
  while (select.step()) {
    SeriesRecord series{select.text(0), select.integer(1), select.integer(2), {}};
    const std::string bytes = select.blob(3);
    for (std::size_t offset = 0; offset + sizeof(double) <= bytes.size(); offset += sizeof(double)) {
      double value = 0.0;
      std::memcpy(&value, bytes.data() + offset, sizeof value);
      series.values.push_back(std::isnan(value) ? std::nullopt : std::optional(value));
    }
    list.push_back(std::move(series));
  }
  return list;
}

std::string Store::secret(const std::string& name) {
  std::lock_guard lock(mutex_);
  // Made and kept in one statement: two processes sharing the file agree on the first one kept.
  Statement insert = db_->prepare("INSERT OR IGNORE INTO secrets (name, value) VALUES (?1, ?2)");
  insert.bind(1, name).bind(2, core::unguessable_id('k').substr(1));
  insert.run();
  Statement select = db_->prepare("SELECT value FROM secrets WHERE name = ?1");
  select.bind(1, name);
  if (!select.step()) throw core::Error(core::ErrorCode::storage, "the database keeps no secret '" + name + "'");
  return select.text(0);
}

bool Store::has_episode(const std::string& id) {
  std::lock_guard lock(mutex_);
  Statement select = db_->prepare("SELECT 1 FROM episodes WHERE id = ?1");
  select.bind(1, id);
  return select.step();
}

std::optional<EpisodeRecord> Store::episode(const std::string& id) {
  std::lock_guard lock(mutex_);
  Statement select = db_->prepare("SELECT " + std::string(kEpisodeColumns) + " FROM episodes WHERE id = ?1");
  select.bind(1, id);
  if (!select.step()) return std::nullopt;
  EpisodeRecord episode = read_episode(select);
  episode.metrics = read_metrics(*db_, id);

  Statement events =
      db_->prepare("SELECT tick, time, kind, subject, data FROM events WHERE episode_id = ?1 ORDER BY seq");
  events.bind(1, id);
  while (events.step()) {
    episode.events.push_back(
        {events.integer(0), events.real(1), events.text(2), events.text(3), core::parse_bounded_json(events.text(4), "an event's data")});
  }

  Statement samples = db_->prepare(
      "SELECT agent_id, tick, x, y, theta FROM trajectory_samples WHERE episode_id = ?1 ORDER BY agent_id, tick");
  samples.bind(1, id);
  while (samples.step()) {
    episode.trajectory.push_back(
        {samples.text(0), samples.integer(1), samples.real(2), samples.real(3), samples.real(4)});
  }
  return episode;
}

std::vector<std::string> Store::episode_ids_of_run(const std::string& run_id) {
  std::lock_guard lock(mutex_);
  Statement select = db_->prepare("SELECT id FROM episodes WHERE run_id = ?1 ORDER BY rowid");
  select.bind(1, run_id);
  std::vector<std::string> ids;
  while (select.step()) ids.push_back(select.text(0));
  return ids;
}

std::vector<EpisodeRecord> Store::episodes_of_run(const std::string& run_id) {
  std::lock_guard lock(mutex_);
  Statement select = db_->prepare("SELECT " + std::string(kEpisodeColumns) + " FROM episodes WHERE run_id = ?1 ORDER BY seed, rowid");
  select.bind(1, run_id);
  std::vector<EpisodeRecord> list;
  while (select.step()) {
    list.push_back(read_episode(select));
    list.back().metrics = read_metrics(*db_, list.back().id);
  }
  return list;
}

void remove_database(const std::filesystem::path& path) {
  std::error_code ignored;
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path.string() + suffix, ignored);
}

std::vector<RunRecord> Store::all_runs() {
  std::lock_guard lock(mutex_);
  Statement select = db_->prepare("SELECT " + std::string(kRunColumns) + " FROM runs ORDER BY rowid");
  std::vector<RunRecord> list;
  while (select.step()) list.push_back(read_run(select));
  return list;
}

Store::Batch::Batch(Store& store) : store_(store), lock_(store.mutex_), transaction_(std::make_unique<Transaction>(*store.db_)) {}

Store::Batch::~Batch() = default;

void Store::Batch::put_scenario_if_missing(const ScenarioRecord& scenario) {
  Database& db = *store_.db_;
  Statement exists = db.prepare("SELECT 1 FROM scenarios WHERE id = ?1");
  exists.bind(1, scenario.id);
  if (exists.step()) return;
  Statement insert = db.prepare(
      "INSERT INTO scenarios (id, name, format, source, sha256, created_at, summary, owner) VALUES (?1, ?2, ?3, ?4, ?5, ?6, nullif(?7, ''), ?8)");
  insert.bind(1, scenario.id).bind(2, scenario.name).bind(3, scenario.format).bind(4, scenario.source);
  insert.bind(5, scenario_sha256(scenario.source, scenario.files)).bind(6, scenario.created_at).bind(7, scenario.summary).bind(8, scenario.owner);
  insert.run();
  for (const auto& [path, bytes] : scenario.files) {
    Statement file = db.prepare("INSERT INTO scenario_files (scenario_id, path, content) VALUES (?1, ?2, ?3)");
    file.bind(1, scenario.id).bind(2, path).bind_blob(3, bytes);
    file.run();
  }
}

void Store::Batch::put_run(const RunRecord& run) {
  Database& db = *store_.db_;
  Statement update = db.prepare("UPDATE runs SET config = ?2, status = ?3, finished_at = ?4, summary = NULL WHERE id = ?1");
  update.bind(1, run.id).bind(2, core::json_text(run.config)).bind(3, run.status).bind(4, run.finished_at);
  update.run();
  if (db.changes() > 0) return;
  Statement insert = db.prepare(
      "INSERT INTO runs (id, scenario_id, controller, config, status, created_at, finished_at, owner, name, tags, notes)"
      " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11)");
  insert.bind(1, run.id).bind(2, run.scenario_id).bind(3, run.controller).bind(4, core::json_text(run.config)).bind(5, run.status);
  insert.bind(6, run.created_at).bind(7, run.finished_at).bind(8, run.owner).bind(9, run.name);
  insert.bind(10, core::json_text(nlohmann::json(run.tags))).bind(11, run.notes);
  insert.run();
}

void Store::Batch::write_episode(const EpisodeRecord& episode) { store_.insert_episode_rows(episode); }

void Store::Batch::commit() { transaction_->commit(); }

std::string Store::sqlite_version() { return sqlite3_libversion(); }

}  // namespace hrisim::storage
