#pragma once
// Reading attributes of XML elements with errors that name the element, the attribute and the line;
// shared by the importers. tinyxml2 stays in the importers' .cpp files.
#include <optional>
#include <string>
#include <string_view>

#include "scenario/import.hpp"

namespace tinyxml2 {
class XMLDocument;
class XMLElement;
}  // namespace tinyxml2

namespace hrisim::scenario {

/// Deeper element nesting than this is refused before tinyxml2 parses, by one linear pass at the line of
/// the element too deep: IMHuS and Pedsim files nest at most five, and a deep document (200,000 levels)
/// cost 84 s of CPU before tinyxml2's own depth error (its limit, 100, is above this).
inline constexpr int kMaxXmlDepth = 64;

class XmlReader {
 public:
  explicit XmlReader(ImportResult& result) : result_(result) {}

  ImportResult& result() { return result_; }
  void fail(const tinyxml2::XMLElement* element, const std::string& message);
  void warn(const tinyxml2::XMLElement* element, const std::string& message);

  /// A required attribute; an error when absent.
  std::optional<std::string> text(const tinyxml2::XMLElement* element, const char* attribute);
  /// A required number; an error when absent or not a number.
  std::optional<double> number(const tinyxml2::XMLElement* element, const char* attribute);
  /// An optional number; an error (and nothing) when present but not a number.
  std::optional<double> optional_number(const tinyxml2::XMLElement* element, const char* attribute);

 private:
  ImportResult& result_;
};

/// False (and the error, at its line) when the text is not UTF-8: names read from it end up in JSON.
/// Every importer checks this first.
bool check_utf8(std::string_view text, ImportResult& result);

/// Parses the document; on malformed XML records the error with its line and returns false.
bool parse_xml(std::string_view xml, tinyxml2::XMLDocument& document, ImportResult& result);

}  // namespace hrisim::scenario
