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

int line_at(std::string_view text, std::size_t offset) {
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(std::min(offset, text.size())), '\n'));
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
  const auto unfinished = [&](std::size_t at, const std::string& what) {
    return ImportMessage{line_at(xml, at), what + " at line " + std::to_string(line_at(xml, at)) + " is never finished"};
  };
  for (std::size_t i = xml.find('<'); i != std::string_view::npos; i = xml.find('<', i + 1)) {
    // Comments, CDATA, processing instructions and declarations hold no elements ("<!" last: the
    // others begin with it too).
    static constexpr std::tuple<std::string_view, std::string_view, const char*> kSections[] = {
        {"<!--", "-->", "a comment"}, {"<![CDATA[", "]]>", "a CDATA section"}, {"<?", "?>", "a processing instruction"}, {"<!", ">", "a declaration"}};
    const auto section = std::find_if(std::begin(kSections), std::end(kSections), [&](const auto& s) { return xml.substr(i).starts_with(std::get<0>(s)); });
    if (section != std::end(kSections)) {
      const std::size_t close = xml.find(std::get<1>(*section), i);
      if (close == std::string_view::npos) return unfinished(i, std::get<2>(*section));
      i = close;
      continue;
    }
    const bool closing = i + 1 < xml.size() && xml[i + 1] == '/';
    std::size_t name_end = i + (closing ? 2 : 1);
    while (name_end < xml.size() && !std::isspace(static_cast<unsigned char>(xml[name_end])) && xml[name_end] != '>' && xml[name_end] != '/') ++name_end;
    const std::string name(xml.substr(i + (closing ? 2 : 1), name_end - i - (closing ? 2 : 1)));
    // The tag's end, past quoted attribute values.
    std::size_t end = name_end;
    char quote = 0;
    while (end < xml.size() && (quote || xml[end] != '>')) {
      if (quote && xml[end] == quote) quote = 0;
      else if (!quote && (xml[end] == '"' || xml[end] == '\'')) quote = xml[end];
      ++end;
    }
    const int line = line_at(xml, i);
    if (end >= xml.size()) return unfinished(i, "the tag <" + std::string(closing ? "/" : "") + name + ">");
    if (closing) {
      if (open.empty()) break;  // past the last element: TinyXML stops reading there too
      if (open.back().name != name) {
        return ImportMessage{open.back().line, "<" + open.back().name + "> opened at line " + std::to_string(open.back().line) +
                                                   " is never closed (</" + name + "> at line " + std::to_string(line) + " comes first)"};
      }
      open.pop_back();
    } else if (xml[end - 1] != '/') {
      open.push_back({name, line});
    }
    i = end;
  }
  if (!open.empty()) return ImportMessage{open.back().line, "<" + open.back().name + "> opened at line " + std::to_string(open.back().line) + " is never closed"};
  return std::nullopt;
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
  result.errors.push_back({line_at(text, *bad), "the document is not UTF-8 (byte " + std::to_string(*bad) + ")"});
  return false;
}

bool parse_xml(std::string_view xml, tinyxml2::XMLDocument& document, ImportResult& result) {
  // XML without an encoding declaration is UTF-8; tinyxml2 does not check it, and names read from it
  // end up in JSON.
  if (!check_utf8(xml, result)) return false;
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
