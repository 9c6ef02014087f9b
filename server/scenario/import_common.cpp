#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <tuple>
#include <vector>

#include "core/files.hpp"
#include "core/text.hpp"
#include "scenario/import.hpp"
#include "scenario/xml_reader.hpp"

namespace hrisim::scenario {
namespace {

std::string where(const tinyxml2::XMLElement* element) {
  return element ? "<" + std::string(element->Name()) + ">: " : "";
}

/// Lines of offsets met in increasing order, counted as the scan goes: linear in the text, where
/// counting from its start at each tag made a deep document cost quadratic time.
class LineCounter {
 public:
  explicit LineCounter(std::string_view text) : text_(text) {}
  /// The 1-based line of `offset`; counted again from the start for an offset before the last one.
  int line_at(std::size_t offset) {
    offset = std::min(offset, text_.size());
    if (offset < counted_to_) {
      counted_to_ = 0;
      line_ = 1;
    }
    line_ += static_cast<int>(std::count(text_.begin() + static_cast<std::ptrdiff_t>(counted_to_), text_.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
    counted_to_ = offset;
    return line_;
  }

 private:
  std::string_view text_;
  std::size_t counted_to_ = 0;
  int line_ = 1;
};

/// A tag of an XML document: its name and where it begins and ends.
struct Tag {
  std::size_t at = 0, end = 0;  ///< the '<' and the '>'
  std::string name;
  bool closing = false, self_closing = false;
};

/// Something the tag scan found never finished: where it begins and what it is, in words.
struct Unfinished {
  std::size_t at = 0;
  std::string what;
};

/// Gives each tag of `xml` in order to `visit` (which returns false to stop), past comments, CDATA,
/// processing instructions and declarations (which hold no elements) and quoted attribute values:
/// one pass, linear in the text. What is never finished when the scan ends there.
template <typename Visit>
std::optional<Unfinished> scan_tags(std::string_view xml, Visit visit) {
  for (std::size_t i = xml.find('<'); i != std::string_view::npos; i = xml.find('<', i + 1)) {
    // "<!" last: the others begin with it too.
    static constexpr std::tuple<std::string_view, std::string_view, const char*> kSections[] = {
        {"<!--", "-->", "a comment"}, {"<![CDATA[", "]]>", "a CDATA section"}, {"<?", "?>", "a processing instruction"}, {"<!", ">", "a declaration"}};
    const auto section = std::find_if(std::begin(kSections), std::end(kSections), [&](const auto& s) { return xml.substr(i).starts_with(std::get<0>(s)); });
    if (section != std::end(kSections)) {
      const std::size_t close = xml.find(std::get<1>(*section), i);
      if (close == std::string_view::npos) return Unfinished{i, std::get<2>(*section)};
      i = close;
      continue;
    }
    Tag tag;
    tag.at = i;
    tag.closing = i + 1 < xml.size() && xml[i + 1] == '/';
    const std::size_t name_begin = i + (tag.closing ? 2 : 1);
    std::size_t name_end = name_begin;
    while (name_end < xml.size() && !std::isspace(static_cast<unsigned char>(xml[name_end])) && xml[name_end] != '>' && xml[name_end] != '/') ++name_end;
    tag.name = std::string(xml.substr(name_begin, name_end - name_begin));
    std::size_t end = name_end;
    char quote = 0;
    while (end < xml.size() && (quote || xml[end] != '>')) {
      if (quote && xml[end] == quote) quote = 0;
      else if (!quote && (xml[end] == '"' || xml[end] == '\'')) quote = xml[end];
      ++end;
    }
    if (end >= xml.size()) return Unfinished{i, "the tag <" + std::string(tag.closing ? "/" : "") + tag.name + ">"};
    tag.end = end;
    tag.self_closing = !tag.closing && xml[end - 1] == '/';
    if (!visit(tag)) return std::nullopt;
    i = end;
  }
  return std::nullopt;
}

/// What is wrong with XML tinyxml2 refused, in words and at its line, found by following its tags:
/// an element never closed (a closing tag that does not match comes first), a tag, comment or
/// section never finished. None when the tags are sound (the fault is elsewhere: an attribute, an entity).
std::optional<ImportMessage> explain_malformed(std::string_view xml) {
  struct Open {
    std::string name;
    int line;
  };
  std::vector<Open> open;
  LineCounter lines(xml);
  std::optional<ImportMessage> mismatch;
  const auto unfinished = scan_tags(xml, [&](const Tag& tag) {
    const int line = lines.line_at(tag.at);
    if (!tag.closing) {
      if (!tag.self_closing) open.push_back({tag.name, line});
      return true;
    }
    if (open.empty()) return false;  // past the last element: TinyXML stops reading there too
    if (open.back().name != tag.name) {
      mismatch = ImportMessage{open.back().line, "<" + open.back().name + "> opened at line " + std::to_string(open.back().line) +
                                                     " is never closed (</" + tag.name + "> at line " + std::to_string(line) + " comes first)"};
      return false;
    }
    open.pop_back();
    return true;
  });
  if (mismatch) return mismatch;
  if (unfinished) {
    const int line = lines.line_at(unfinished->at);
    return ImportMessage{line, unfinished->what + " at line " + std::to_string(line) + " is never finished"};
  }
  if (!open.empty()) return ImportMessage{open.back().line, "<" + open.back().name + "> opened at line " + std::to_string(open.back().line) + " is never closed"};
  return std::nullopt;
}

/// The element that nests deeper than kMaxXmlDepth, as an error at its line; none when none does. One
/// linear pass before tinyxml2 parses (which recurses once per level).
std::optional<ImportMessage> too_deep(std::string_view xml) {
  int depth = 0;
  std::optional<ImportMessage> found;
  LineCounter lines(xml);
  scan_tags(xml, [&](const Tag& tag) {
    if (tag.closing) {
      depth = std::max(depth - 1, 0);
    } else if (!tag.self_closing && ++depth > kMaxXmlDepth) {
      const int line = lines.line_at(tag.at);
      found = ImportMessage{line, "<" + tag.name + "> at line " + std::to_string(line) + " nests more than " + std::to_string(kMaxXmlDepth) +
                                      " elements deep; IMHuS and Pedsim files nest at most five"};
      return false;
    }
    return true;
  });
  return found;
}

}  // namespace

void XmlReader::fail(const tinyxml2::XMLElement* element, const std::string& message) {
  result_.errors.push_back({element ? element->GetLineNum() : 0, where(element) + message});
}

void XmlReader::warn(const tinyxml2::XMLElement* element, const std::string& message) {
  result_.warnings.push_back({element ? element->GetLineNum() : 0, where(element) + message});
}

std::optional<std::string> XmlReader::text(const tinyxml2::XMLElement* element, const char* attribute) {
  if (const char* value = element->Attribute(attribute)) return std::string(value);
  fail(element, std::string("missing attribute '") + attribute + "'");
  return std::nullopt;
}

std::optional<double> XmlReader::optional_number(const tinyxml2::XMLElement* element, const char* attribute) {
  const char* value = element->Attribute(attribute);
  if (!value) return std::nullopt;
  const auto number = core::parse_number(value);
  if (!number) {
    fail(element, std::string("attribute '") + attribute + "' must be a number, got '" + value + "'");
    return std::nullopt;
  }
  return number;
}

std::optional<double> XmlReader::number(const tinyxml2::XMLElement* element, const char* attribute) {
  if (!element->Attribute(attribute)) {
    fail(element, std::string("missing attribute '") + attribute + "'");
    return std::nullopt;
  }
  return optional_number(element, attribute);
}

bool check_utf8(std::string_view text, ImportResult& result) {
  const auto bad = core::invalid_utf8_offset(text);
  if (!bad) return true;
  result.errors.push_back({LineCounter(text).line_at(*bad), "the document is not UTF-8 (byte " + std::to_string(*bad) + ")"});
  return false;
}

bool parse_xml(std::string_view xml, tinyxml2::XMLDocument& document, ImportResult& result) {
  // XML without an encoding declaration is UTF-8; tinyxml2 does not check it, and names read from it
  // end up in JSON.
  if (!check_utf8(xml, result)) return false;
  if (auto deep = too_deep(xml)) {
    result.errors.push_back(std::move(*deep));
    return false;
  }
  if (document.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS) {
    if (auto explained = explain_malformed(xml)) {
      explained->message = "malformed XML: " + explained->message;
      result.errors.push_back(std::move(*explained));
    } else {
      result.errors.push_back({document.ErrorLineNum(), "malformed XML at line " + std::to_string(document.ErrorLineNum()) + ": " +
                                                            (document.ErrorID() == tinyxml2::XML_ERROR_PARSING_ATTRIBUTE ? "an attribute is not name=\"value\""
                                                             : document.ErrorID() == tinyxml2::XML_ERROR_PARSING_TEXT ? "text that is not XML (an unescaped & or <?)"
                                                             : document.ErrorID() == tinyxml2::XML_ERROR_EMPTY_DOCUMENT ? "the document is empty"
                                                                                                                        : std::string(document.ErrorName()))});
    }
    return false;
  }
  if (!document.FirstChildElement()) {
    result.errors.push_back({0, "the XML document has no elements"});
    return false;
  }
  return true;
}

int origin_line(const ImportResult& imported, std::string_view pointer) {
  std::size_t longest = 0;
  int line = 0;
  for (const auto& [prefix, from] : imported.origins) {
    const bool within = pointer.starts_with(prefix) && (pointer.size() == prefix.size() || pointer[prefix.size()] == '/');
    if (within && prefix.size() >= longest) {
      longest = prefix.size();
      line = from;
    }
  }
  return line;
}

std::string detect_xml_format(std::string_view xml) {
  tinyxml2::XMLDocument document;
  if (document.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS || !document.FirstChildElement()) return "imhus";
  const tinyxml2::XMLElement* root = document.FirstChildElement();
  const std::string name = root->Name();
  return (name == "scenario" || name == "welcome") && !root->NextSiblingElement() ? "pedsim" : "imhus";
}

std::optional<nlohmann::ordered_json> world_from_file(const std::filesystem::path& file, std::string& error) {
  if (!std::filesystem::exists(file)) {
    error = "map " + file.string() + " does not exist";
    return std::nullopt;
  }
  if (file.extension() == ".yaml" || file.extension() == ".yml") {
    return nlohmann::ordered_json{{"map", std::filesystem::absolute(file).string()}};
  }
  try {
    auto world = nlohmann::ordered_json::parse(core::read_file(file));
    if (!world.is_object()) throw std::runtime_error("not a JSON object");
    return world;
  } catch (const std::exception& e) {
    error = "map " + file.string() + " is not a world JSON object: " + e.what();
    return std::nullopt;
  }
}

}  // namespace hrisim::scenario
