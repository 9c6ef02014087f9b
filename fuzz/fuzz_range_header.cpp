// Fuzz target: a Range header against a file's length: the first 8 bytes are the length (little
// endian), the rest the header's value. A part must lie inside the file.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "http/range_header.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 8) return 0;
  std::uint64_t length = 0;
  for (int i = 0; i < 8; ++i) length |= static_cast<std::uint64_t>(data[i]) << (8 * i);
  const std::string_view value(reinterpret_cast<const char*>(data + 8), size - 8);
  const hrisim::http::AskedRange asked = hrisim::http::read_range_header(value, length);
  if (asked.kind == hrisim::http::AskedRange::Kind::part && !(asked.first <= asked.last && asked.last < length)) __builtin_trap();
  return 0;
}
