// Fuzz target: native JSON scenarios, compiled as an upload is (schema, meaning, world, task), then
// summarised and drawn as a map view would be.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_support.hpp"
#include "scenario/source.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto compiled = hrisim::scenario::compile_source(text, hrisim::scenario::SourceFormat::json, hrisim::fuzz::source_options());
  hrisim::fuzz::use(compiled);
  return 0;
}
