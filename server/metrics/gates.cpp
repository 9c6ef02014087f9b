#include "metrics/gates.hpp"

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "metrics/definitions.hpp"

namespace hrisim::metrics {
namespace {

// Two-character operators first so that "<=" is not read as "<".
constexpr std::array<std::string_view, 6> kOperators{"==", "!=", "<=", ">=", "<", ">"};

[[noreturn]] void bad_gate(std::string_view text, const std::string& why) {
  throw core::Error(core::ErrorCode::bad_request, "gate '" + std::string(text) + "': " + why, {{"gate", std::string(text)}});
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

}  // namespace

Gate parse_gate(std::string_view text) {
  Gate gate;
  gate.text = std::string(trim(text));
  const std::string_view body = gate.text;
  std::size_t op_at = std::string_view::npos;
  for (std::size_t i = 0; i < body.size() && op_at == std::string_view::npos; ++i) {
    for (const std::string_view op : kOperators) {
      if (body.substr(i, op.size()) == op) {
        op_at = i;
        gate.op = op;
        break;
      }
    }
  }
  if (op_at == std::string_view::npos) bad_gate(text, "expected `metric.statistic OP number` with OP one of == != < <= > >=");
  const std::string_view left = trim(body.substr(0, op_at)), right = trim(body.substr(op_at + gate.op.size()));
  const auto dot = left.rfind('.');
  if (dot == std::string_view::npos) bad_gate(text, "expected metric.statistic before the operator, e.g. collisions.max");
  gate.metric = left.substr(0, dot);
  gate.statistic = left.substr(dot + 1);
  if (!find_definition(gate.metric)) bad_gate(text, "unknown metric '" + gate.metric + "' (GET /api/v1/metrics lists them)");
  if (!is_statistic(gate.statistic)) {
    bad_gate(text, "unknown statistic '" + gate.statistic + "' (count, nulls, mean, std, min, max, ci95_low, ci95_high)");
  }
  const auto [end, ec] = std::from_chars(right.data(), right.data() + right.size(), gate.threshold);
  if (right.empty() || ec != std::errc() || end != right.data() + right.size() || !std::isfinite(gate.threshold)) {
    bad_gate(text, "expected a finite number after " + gate.op + ", got '" + std::string(right) + "'");
  }
  return gate;
}

GateResult evaluate_gate(const Gate& gate, const Aggregate& aggregate) {
  GateResult result;
  result.actual = statistic(aggregate, gate.statistic);
  if (!result.actual) return result;
  const double a = *result.actual, b = gate.threshold;
  if (gate.op == "==") result.passed = a == b;
  if (gate.op == "!=") result.passed = a != b;
  if (gate.op == "<") result.passed = a < b;
  if (gate.op == "<=") result.passed = a <= b;
  if (gate.op == ">") result.passed = a > b;
  if (gate.op == ">=") result.passed = a >= b;
  return result;
}

}  // namespace hrisim::metrics
