#pragma once
// Gates: pass/fail conditions of a run over its metric aggregates, written `metric.statistic OP number`,
// e.g. `collisions.max == 0`, `minimum_distance_to_people.min >= 0.3`, `success.mean >= 0.9`.
#include <optional>
#include <string>
#include <string_view>

#include "metrics/aggregate.hpp"

namespace hrisim::metrics {

struct Gate {
  std::string text;  ///< as written
  std::string metric;
  std::string statistic;
  std::string op;  ///< ==, !=, <, <=, >, >=
  double threshold = 0.0;
};

/// Parses and checks a gate against the metric definitions; throws core::Error(bad_request) saying
/// what is wrong (unknown metric, unknown statistic, operator, number).
Gate parse_gate(std::string_view text);

struct GateResult {
  bool passed = false;
  std::optional<double> actual;  ///< the statistic's value; empty when it has none (the gate fails)
};

GateResult evaluate_gate(const Gate& gate, const Aggregate& aggregate);

}  // namespace hrisim::metrics
