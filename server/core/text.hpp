#pragma once
// Small text helpers: lists for messages, UTF-8 checks and JSON text that never throws.
#include <cstddef>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <string_view>

namespace hrisim::core {

/// The items with `separator` between them: {"a", "b"} → "a, b".
template <class Range>
std::string join(const Range& items, std::string_view separator = ", ") {
  std::string text;
  for (const auto& item : items) {
    if (!text.empty()) text += separator;
    text += std::string_view(item);
  }
  return text;
}

/// The text with ASCII letters in lower case (HTTP header names, schemes, host names).
std::string lower_case(std::string text);

/// Offset of the first byte that does not belong to well-formed UTF-8 (RFC 3629: no overlong forms,
/// no surrogates, nothing above U+10FFFF), or nullopt when all of `text` is UTF-8.
std::optional<std::size_t> invalid_utf8_offset(std::string_view text);

/// A finite decimal number written as people write them in files: spaces around it and a leading '+'
/// allowed; nullopt for anything else (an empty text, trailing characters, inf, nan).
std::optional<double> parse_number(std::string_view text);

/// The bytes of standard base64 text (RFC 4648 §4, padded; no whitespace), or nullopt when it is not.
std::optional<std::string> base64_decode(std::string_view text);
/// Standard base64 text of bytes (RFC 4648 §4, padded), as base64_decode reads it.
std::string base64_encode(std::string_view bytes);

/// JSON text of a value; bytes of its strings that are not UTF-8 become U+FFFD instead of throwing,
/// so text a client sent (a path, a header) can always be quoted back in an error.
std::string json_text(const nlohmann::json& value, int indent = -1);

}  // namespace hrisim::core
