// Fuzz target: gate expressions of runs (`metric.statistic OP number`), parsed and evaluated.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.hpp"
#include "metrics/gates.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const hrisim::metrics::Gate gate = hrisim::metrics::parse_gate(text);
    const double values[] = {0.0, 1.0, 0.5};
    std::optional<double> samples[] = {values[0], values[1], std::nullopt, values[2]};
    hrisim::metrics::evaluate_gate(gate, hrisim::metrics::aggregate(samples, gate.metric == "success"));
  } catch (const hrisim::core::Error&) {
    // A refusal is the expected answer to a bad gate; anything else (a crash, another exception) is a finding.
  }
  return 0;
}
