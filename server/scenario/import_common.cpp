#include <tinyxml2.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/files.hpp"
#include "core/text.hpp"
#include "scenario/import.hpp"
#include "scenario/xml_reader.hpp"

namespace hrisim::scenario {
namespace {

std::string where(const tinyxml2::XMLElement* element) {
  return element ? "<" + std::string(element->Name()) + ">: " : "";
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
  std::string_view text(value);
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  double number = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), number);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || !std::isfinite(number)) {
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

bool parse_xml(std::string_view xml, tinyxml2::XMLDocument& document, ImportResult& result) {
  // XML without an encoding declaration is UTF-8; tinyxml2 does not check it, and names read from it
  // end up in JSON.
  if (const auto bad = core::invalid_utf8_offset(xml)) {
    const auto line = 1 + std::count(xml.begin(), xml.begin() + static_cast<std::ptrdiff_t>(*bad), '\n');
    result.errors.push_back({static_cast<int>(line), "the document is not UTF-8 (byte " + std::to_string(*bad) + ")"});
    return false;
  }
  if (document.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS) {
    result.errors.push_back({document.ErrorLineNum(), std::string("malformed XML: ") + document.ErrorStr()});
    return false;
  }
  if (!document.FirstChildElement()) {
    result.errors.push_back({0, "the XML document has no elements"});
    return false;
  }
  return true;
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
