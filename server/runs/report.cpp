#include "runs/report.hpp"

#include <algorithm>
#include <map>
#include <numeric>
#include <sstream>

#include "metrics/aggregate.hpp"
#include "metrics/compare.hpp"
#include "metrics/definitions.hpp"

namespace hrisim::runs {
namespace {

using nlohmann::json;

json optional_json(const std::optional<double>& value) { return value ? json(*value) : json(); }

json aggregate_json(const metrics::Aggregate& a) {
  return {{"count", a.count},
          {"nulls", a.nulls},
          {"mean", optional_json(a.mean)},
          {"std", optional_json(a.std)},
          {"min", optional_json(a.min)},
          {"max", optional_json(a.max)},
          {"ci95_low", optional_json(a.ci95_low)},
          {"ci95_high", optional_json(a.ci95_high)}};
}

const storage::MetricValue* find_metric(const storage::EpisodeRecord& episode, std::string_view key) {
  for (const storage::MetricValue& metric : episode.metrics) {
    if (metric.key == key) return &metric;
  }
  return nullptr;
}

/// A metric's value in each finished episode (empty where it has none), in order.
std::vector<std::optional<double>> finished_values(const std::vector<storage::EpisodeRecord>& episodes, std::string_view key) {
  std::vector<std::optional<double>> values;
  for (const storage::EpisodeRecord& episode : episodes) {
    if (episode.status != "finished") continue;
    const storage::MetricValue* metric = find_metric(episode, key);
    values.push_back(metric ? metric->value : std::nullopt);
  }
  return values;
}

std::string xml_escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string number_text(const json& value) { return value.is_null() ? "no value" : value.dump(); }

}  // namespace

json metric_json(const storage::MetricValue& metric) { return optional_json(metric.value); }

std::vector<metrics::Gate> gates_of(const storage::RunRecord& run) {
  std::vector<metrics::Gate> gates;
  for (const json& text : run.config.value("gates", json::array())) gates.push_back(metrics::parse_gate(text.get<std::string>()));
  return gates;
}

json run_report(const storage::RunRecord& run, const std::vector<storage::EpisodeRecord>& episodes,
                const std::map<std::uint64_t, std::string>& live) {
  std::map<std::uint64_t, const storage::EpisodeRecord*> by_seed;
  for (const storage::EpisodeRecord& episode : episodes) by_seed[episode.seed] = &episode;

  // Seeds not stored and not live: the run was cancelled, the server stopped, or — once the run has
  // ended otherwise — their episodes ran but could not be stored (a full disk): an error.
  const std::string not_run = run.status == "cancelled" ? "cancelled" : run.status == "interrupted" ? "interrupted"
                              : run.status == "failed" || run.status == "finished" ? "error" : "queued";
  std::map<std::string, int> counts{{"queued", 0}, {"running", 0}, {"finished", 0}, {"error", 0}, {"cancelled", 0}, {"interrupted", 0}};
  json list = json::array();
  const json seeds = run.config.value("seeds", json::array());
  for (const json& seed_json : seeds) {
    const auto seed = seed_json.get<std::uint64_t>();
    json item{{"seed", seed}};
    if (const auto stored = by_seed.find(seed); stored != by_seed.end()) {
      const storage::EpisodeRecord& episode = *stored->second;
      item["status"] = episode.status;
      item["episode_id"] = episode.id;
      item["termination"] = episode.termination_reason;
      item["sim_time"] = episode.sim_time;
      const storage::MetricValue* success = find_metric(episode, "success");
      item["success"] = success ? metric_json(*success) : json();
    } else if (const auto running = live.find(seed); running != live.end()) {
      item["status"] = running->second;
    } else {
      item["status"] = not_run;
    }
    ++counts[item["status"].get<std::string>()];
    list.push_back(std::move(item));
  }

  std::map<std::string, metrics::Aggregate, std::less<>> by_key;
  json aggregates = json::object();
  for (const metrics::Definition& definition : metrics::definitions()) {
    const metrics::Aggregate& stats = by_key[std::string(definition.key)] =
        metrics::aggregate(finished_values(episodes, definition.key), definition.unit == "bool");
    aggregates[std::string(definition.key)] = aggregate_json(stats);
  }
  // Rates over finished episodes, as their own lines.
  const auto rate = [&](const char* key, auto counts_as) {
    int hits = 0, total = 0;
    for (const auto& value : finished_values(episodes, key)) {
      if (!value) continue;
      ++total;
      hits += counts_as(*value);
    }
    return total == 0 ? json() : json(static_cast<double>(hits) / total);
  };
  const json rates{{"success_rate", rate("success", [](double v) { return v == 1.0; })},
                   {"collision_rate", rate("collisions", [](double v) { return v > 0.0; })}};

  json gate_results = json::array(), reasons = json::array();
  bool passed = true;
  for (const metrics::Gate& gate : gates_of(run)) {
    const metrics::GateResult result = metrics::evaluate_gate(gate, by_key.at(gate.metric));
    gate_results.push_back({{"gate", gate.text},
                            {"metric", gate.metric},
                            {"statistic", gate.statistic},
                            {"op", gate.op},
                            {"threshold", gate.threshold},
                            {"actual", optional_json(result.actual)},
                            {"passed", result.passed}});
    if (!result.passed) {
      passed = false;
      reasons.push_back("gate '" + gate.text + "' failed: " + gate.metric + "." + gate.statistic + " is " +
                        number_text(optional_json(result.actual)));
    }
  }
  bool complete = counts["finished"] + counts["error"] == static_cast<int>(seeds.size());
  if (!complete) reasons.push_back("the run is " + run.status + ": " + std::to_string(counts["finished"]) + " of " +
                                   std::to_string(seeds.size()) + " episodes finished");
  // A merge of shards is complete once every shard is in it.
  if (const json sharding = run.config.value("sharding", json()); sharding.contains("merged")) {
    const int count = sharding.value("count", 0);
    const auto merged = sharding["merged"].get<std::vector<int>>();
    if (static_cast<int>(merged.size()) < count) {
      complete = false;
      std::string missing;
      for (int shard = 1, shown = 0; shard <= count && shown < 10; ++shard) {
        if (std::find(merged.begin(), merged.end(), shard) != merged.end()) continue;
        missing += (missing.empty() ? "" : ", ") + std::to_string(shard);
        ++shown;
      }
      if (count - static_cast<int>(merged.size()) > 10) missing += ", ...";
      reasons.push_back(std::to_string(merged.size()) + " of " + std::to_string(count) + " shards are merged (missing: " + missing + "): " +
                        std::to_string(seeds.size()) + " of " + std::to_string(sharding.value("of_seeds", json::array()).size()) + " seeds");
    }
  }
  if (counts["error"] > 0) reasons.push_back(std::to_string(counts["error"]) + " episode(s) ended in error");
  passed = passed && complete && counts["error"] == 0;

  return {{"id", run.id},
          {"name", run.name},
          {"tags", run.tags},
          {"notes", run.notes},
          {"scenario", run.config.value("scenario", run.scenario_id)},
          {"scenario_record", run.scenario_id},
          {"controller", run.controller},
          {"status", run.status},
          {"created_at", run.created_at},
          {"finished_at", run.finished_at ? json(*run.finished_at) : json()},
          {"config", run.config},
          {"progress", {{"total", seeds.size()}, {"finished", counts["finished"]}, {"error", counts["error"]},
                        {"running", counts["running"]}, {"queued", counts["queued"]}, {"cancelled", counts["cancelled"]},
                        {"interrupted", counts["interrupted"]}}},
          {"episodes", list},
          {"aggregates", aggregates},
          {"rates", rates},
          {"verdict", {{"passed", passed}, {"complete", complete}, {"gates", gate_results}, {"reasons", reasons}}}};
}

namespace {

/// A metric's non-null values in the finished episodes.
std::vector<double> values_of(const std::vector<storage::EpisodeRecord>& episodes, std::string_view key) {
  std::vector<double> values;
  for (const auto& value : finished_values(episodes, key)) {
    if (value) values.push_back(*value);
  }
  return values;
}

json mean_of(const std::vector<double>& values) {
  return values.empty() ? json() : json(std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size()));
}

/// The test of two runs' values of a metric: Fisher's exact test for 0/1 metrics, else Welch's t-test.
std::pair<std::string, std::optional<double>> test_of(const metrics::Definition& definition, const std::vector<double>& a,
                                                      const std::vector<double>& b) {
  if (definition.unit != "bool") return {"welch_t", metrics::welch_p_value(a, b)};
  if (a.empty() || b.empty()) return {"fisher_exact", std::nullopt};
  const auto hits = [](const std::vector<double>& v) { return static_cast<int>(std::count(v.begin(), v.end(), 1.0)); };
  return {"fisher_exact", metrics::fisher_exact_p_value(hits(a), static_cast<int>(a.size()), hits(b), static_cast<int>(b.size()))};
}

/// better, worse (by the metric's direction), different (it has none), or no significant change.
std::string change_of(const metrics::Definition& definition, bool significant, const json& difference) {
  if (!significant) return "no significant change";
  if (definition.better == metrics::Better::none) return "different";
  return (difference.get<double>() > 0.0) == (definition.better == metrics::Better::higher) ? "better" : "worse";
}

/// Quantile q of sorted values, linearly between the two nearest (Hyndman and Fan's type 7, as R's
/// default and NumPy's).
double quantile(const std::vector<double>& sorted, double q) {
  const double at = q * static_cast<double>(sorted.size() - 1);
  const auto below = static_cast<std::size_t>(at);
  const double fraction = at - static_cast<double>(below);
  return below + 1 < sorted.size() ? sorted[below] + fraction * (sorted[below + 1] - sorted[below]) : sorted[below];
}

/// A run's values of a metric for a box or strip plot: count, mean, std, the five numbers and the values.
json distribution_of(const std::string& run, std::vector<double> values) {
  const metrics::Aggregate aggregate = metrics::aggregate(std::vector<std::optional<double>>(values.begin(), values.end()), false);
  json item{{"run", run}, {"count", values.size()}, {"mean", mean_of(values)}, {"std", optional_json(aggregate.std)}, {"values", values}};
  std::sort(values.begin(), values.end());
  for (const auto& [name, q] : {std::pair{"min", 0.0}, {"q1", 0.25}, {"median", 0.5}, {"q3", 0.75}, {"max", 1.0}}) {
    item[name] = values.empty() ? json() : json(quantile(values, q));
  }
  return item;
}

}  // namespace

json compare_runs(const storage::RunRecord& a, const std::vector<storage::EpisodeRecord>& a_episodes, const storage::RunRecord& b,
                  const std::vector<storage::EpisodeRecord>& b_episodes) {
  json items = json::array();
  for (const metrics::Definition& definition : metrics::definitions()) {
    const std::vector<double> va = values_of(a_episodes, definition.key), vb = values_of(b_episodes, definition.key);
    const auto [test, p] = test_of(definition, va, vb);
    json item{{"key", definition.key},
              {"unit", definition.unit},
              {"better", metrics::to_string(definition.better)},
              {"a", {{"count", va.size()}, {"mean", mean_of(va)}}},
              {"b", {{"count", vb.size()}, {"mean", mean_of(vb)}}},
              {"difference", va.empty() || vb.empty() ? json() : json(mean_of(vb).get<double>() - mean_of(va).get<double>())},
              {"test", test},
              {"p_value", optional_json(p)}};
    const bool significant = p && *p < metrics::kSignificanceLevel;
    item["significant"] = significant;
    item["change"] = change_of(definition, significant, item["difference"]);
    items.push_back(std::move(item));
  }
  return {{"a", a.id}, {"b", b.id}, {"significance_level", metrics::kSignificanceLevel}, {"metrics", items}};
}

json compare_many_runs(const std::vector<RunWithEpisodes>& runs, bool holm) {
  json items = json::array();
  std::vector<std::optional<double>> p_values;  // every test of the reply, in order: the family Holm adjusts
  for (const metrics::Definition& definition : metrics::definitions()) {
    std::vector<std::vector<double>> values;
    json distributions = json::array();
    for (const RunWithEpisodes& run : runs) {
      values.push_back(values_of(*run.episodes, definition.key));
      distributions.push_back(distribution_of(run.run->id, values.back()));
    }
    json comparisons = json::array();
    for (std::size_t r = 1; r < runs.size(); ++r) {
      const auto [test, p] = test_of(definition, values[0], values[r]);
      p_values.push_back(p);
      comparisons.push_back({{"run", runs[r].run->id},
                             {"difference", values[0].empty() || values[r].empty() ? json()
                                                                                   : json(mean_of(values[r]).get<double>() - mean_of(values[0]).get<double>())},
                             {"test", test},
                             {"p_value", optional_json(p)}});
    }
    items.push_back({{"key", definition.key},
                     {"unit", definition.unit},
                     {"better", metrics::to_string(definition.better)},
                     {"runs", distributions},
                     {"comparisons", comparisons}});
  }
  const std::vector<std::optional<double>> adjusted = holm ? metrics::holm_adjusted(p_values) : p_values;
  std::size_t test = 0;
  std::size_t tests = 0;
  for (const auto& p : p_values) tests += p.has_value();
  for (std::size_t m = 0; m < items.size(); ++m) {
    const metrics::Definition& definition = metrics::definitions()[m];
    for (json& comparison : items[m]["comparisons"]) {
      const std::optional<double>& p = adjusted[test++];
      const bool significant = p && *p < metrics::kSignificanceLevel;
      comparison["p_adjusted"] = optional_json(p);
      comparison["significant"] = significant;
      comparison["change"] = change_of(definition, significant, comparison["difference"]);
    }
  }
  json ids = json::array();
  for (const RunWithEpisodes& run : runs) ids.push_back(run.run->id);
  return {{"runs", ids},
          {"baseline", ids[0]},
          {"significance_level", metrics::kSignificanceLevel},
          {"correction", holm ? "holm" : "none"},
          {"tests", tests},
          {"metrics", items}};
}

std::string junit_xml(const json& report) {
  std::ostringstream cases;
  int tests = 0, failures = 0;
  const std::string suite = "hrisim run " + report["id"].get<std::string>();
  for (const json& gate : report["verdict"]["gates"]) {
    ++tests;
    cases << "    <testcase classname=\"" << xml_escape(suite) << ".gates\" name=\"" << xml_escape(gate["gate"]) << "\">\n";
    if (!gate["passed"].get<bool>()) {
      ++failures;
      cases << "      <failure message=\"" << xml_escape(gate["metric"].get<std::string>() + "." + gate["statistic"].get<std::string>()) << " is "
            << xml_escape(number_text(gate["actual"])) << "\"/>\n";
    }
    cases << "    </testcase>\n";
  }
  for (const json& episode : report["episodes"]) {
    // Unsuccessful episodes are the gates' business (success.mean); here only those that did not finish.
    const std::string status = episode["status"];
    if (status == "finished") continue;
    ++tests;
    ++failures;
    cases << "    <testcase classname=\"" << xml_escape(suite) << ".episodes\" name=\"seed " << episode["seed"].dump() << "\">\n"
          << "      <failure message=\"episode " << xml_escape(status) << "\"/>\n    </testcase>\n";
  }
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites tests=\"" << tests << "\" failures=\"" << failures << "\">\n"
      << "  <testsuite name=\"" << xml_escape(suite) << "\" tests=\"" << tests << "\" failures=\"" << failures << "\">\n"
      << cases.str() << "  </testsuite>\n</testsuites>\n";
  return xml.str();
}

}  // namespace hrisim::runs
