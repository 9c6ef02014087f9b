// Fuzz target: HuNavSim agents YAML, imported and compiled as an upload is.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_support.hpp"
#include "scenario/source.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  hrisim::fuzz::use(hrisim::scenario::compile_source(text, hrisim::scenario::SourceFormat::hunav_yaml, hrisim::fuzz::source_options()));
  return 0;
}
