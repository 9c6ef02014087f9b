#pragma once
// The Range request header of a file download (RFC 9110 §14.1–14.2), read as a free function so
// that it can be tested and fuzzed without a server.
#include <cstdint>
#include <string_view>

namespace hrisim::http {

/// What a Range header asks of a representation of some length.
struct AskedRange {
  enum class Kind {
    whole,          ///< no Range, another unit, several ranges or an invalid one: ignored, 200 and the whole file
    part,           ///< one satisfiable range: 206 with bytes [first, last]
    unsatisfiable,  ///< one valid range outside the file: 416 with `Content-Range: bytes */LENGTH`
  };
  Kind kind = Kind::whole;
  std::uint64_t first = 0;  ///< first byte of a part
  std::uint64_t last = 0;   ///< last byte of a part, inclusive
};

/// Reads a Range header's value (`bytes=FIRST-LAST`, `bytes=FIRST-`, `bytes=-SUFFIX`; the unit in any
/// case) against a representation of `length` bytes. Per RFC 9110 a range-spec that is not valid
/// (`bytes= 0-1`, `bytes=+1-2`, `bytes=5-3`) makes the whole header ignored, not refused; so is a
/// list of several ranges, which this server does not send as multipart.
AskedRange read_range_header(std::string_view value, std::uint64_t length);

}  // namespace hrisim::http
