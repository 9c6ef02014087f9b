#include "http/range_header.hpp"

#include <algorithm>
#include <cctype>
#include <limits>
#include <optional>

namespace hrisim::http {
namespace {

bool is_ows(char c) { return c == ' ' || c == '\t'; }

/// 1*DIGIT; a value past 2^64 - 1 saturates (it is past any file's end all the same).
std::optional<std::uint64_t> digits(std::string_view text) {
  if (text.empty()) return std::nullopt;
  std::uint64_t value = 0;
  for (const char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
    const auto digit = static_cast<std::uint64_t>(c - '0');
    constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();
    value = value > (kMax - digit) / 10 ? kMax : value * 10 + digit;
  }
  return value;
}

/// One byte range-spec: int-range (`FIRST-` or `FIRST-LAST`, LAST not below FIRST) or suffix-range
/// (`-SUFFIX`); nothing when it is neither.
struct Spec {
  std::optional<std::uint64_t> first, last;  ///< no first: a suffix of `last` bytes
};
std::optional<Spec> read_spec(std::string_view text) {
  const std::size_t dash = text.find('-');
  if (dash == std::string_view::npos) return std::nullopt;
  const std::string_view before = text.substr(0, dash), after = text.substr(dash + 1);
  if (before.empty()) {
    const auto suffix = digits(after);
    if (!suffix) return std::nullopt;
    return Spec{std::nullopt, suffix};
  }
  const auto first = digits(before);
  if (!first) return std::nullopt;
  if (after.empty()) return Spec{first, std::nullopt};
  const auto last = digits(after);
  if (!last || *last < *first) return std::nullopt;
  return Spec{first, last};
}

}  // namespace

AskedRange read_range_header(std::string_view value, std::uint64_t length) {
  // The field value comes without its surrounding whitespace; the unit is a case-insensitive token.
  while (!value.empty() && is_ows(value.front())) value.remove_prefix(1);
  while (!value.empty() && is_ows(value.back())) value.remove_suffix(1);
  const std::size_t equals = value.find('=');
  if (equals == std::string_view::npos) return {};
  const std::string_view unit = value.substr(0, equals);
  const bool bytes = unit.size() == 5 && std::equal(unit.begin(), unit.end(), "bytes", [](char a, char b) {
                       return std::tolower(static_cast<unsigned char>(a)) == b;
                     });
  if (!bytes) return {};
  // range-set = 1#range-spec: elements split by OWS "," OWS; empty elements are allowed and skipped,
  // but nothing may stand between "=" and the first element.
  std::optional<Spec> only;
  std::size_t specs = 0;
  std::string_view rest = value.substr(equals + 1);
  for (bool first_element = true;; first_element = false) {
    const std::size_t comma = rest.find(',');
    std::string_view element = rest.substr(0, comma);
    if (!first_element) {
      while (!element.empty() && is_ows(element.front())) element.remove_prefix(1);
    }
    if (comma != std::string_view::npos) {
      while (!element.empty() && is_ows(element.back())) element.remove_suffix(1);
    }
    if (!element.empty()) {
      only = read_spec(element);
      if (!only) return {};
      ++specs;
    }
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  if (specs != 1) return {};
  if (!only->first) {
    // A suffix of 0 bytes selects nothing; of an empty file there is nothing to select a part of.
    if (*only->last == 0) return {AskedRange::Kind::unsatisfiable};
    if (length == 0) return {};
    return {AskedRange::Kind::part, length - std::min(length, *only->last), length - 1};
  }
  if (*only->first >= length) return {AskedRange::Kind::unsatisfiable};
  return {AskedRange::Kind::part, *only->first, std::min(only->last.value_or(length - 1), length - 1)};
}

}  // namespace hrisim::http
