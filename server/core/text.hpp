#pragma once
// Small text helpers for messages.
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

}  // namespace hrisim::core
