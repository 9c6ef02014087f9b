#include "scenario/source.hpp"

namespace hrisim::scenario {

std::string_view to_string(SourceFormat format) {
  switch (format) {
    case SourceFormat::json: return "json";
    case SourceFormat::imhus_xml: return "imhus_xml";
    case SourceFormat::pedsim_xml: return "pedsim_xml";
  }
  return "json";
}

std::optional<SourceFormat> source_format(std::string_view name) {
  if (name == "json") return SourceFormat::json;
  if (name == "imhus" || name == "imhus_xml") return SourceFormat::imhus_xml;
  if (name == "pedsim" || name == "pedsim_xml") return SourceFormat::pedsim_xml;
  return std::nullopt;
}

SourceFormat detect_source_format(std::string_view text) {
  const std::size_t first = text.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
  if (first == std::string_view::npos || text[first] != '<') return SourceFormat::json;
  return detect_xml_format(text) == "pedsim" ? SourceFormat::pedsim_xml : SourceFormat::imhus_xml;
}

nlohmann::json SourceIssue::to_json() const {
  nlohmann::json issue = line > 0 ? nlohmann::json{{"line", line}} : nlohmann::json{{"pointer", pointer}};
  issue["message"] = message;
  return issue;
}

CompiledSource compile_source(std::string_view text, SourceFormat format, const SourceOptions& options) {
  CompiledSource compiled;
  compiled.format = format;
  auto adopt = [&](const LoadResult& loaded) {
    for (const auto& error : loaded.errors) compiled.errors.push_back({error.pointer, 0, error.message});
    for (const auto& warning : loaded.warnings) compiled.warnings.push_back({warning.pointer, 0, warning.message});
    compiled.model = loaded.model;
  };
  if (format == SourceFormat::json) {
    // Parsed once here to keep the document; load_scenario_text words the syntax errors.
    const nlohmann::json document = nlohmann::json::parse(text, nullptr, false);
    if (document.is_discarded()) {
      adopt(load_scenario_text(text, options.load));
      return compiled;
    }
    compiled.document = document;
    adopt(load_scenario(document, options.load));
    return compiled;
  }
  const ImportResult imported =
      format == SourceFormat::imhus_xml ? import_imhus(text, options.import) : import_pedsim(text, options.import);
  for (const auto& error : imported.errors) compiled.errors.push_back({"", std::max(error.line, 1), error.message});
  for (const auto& warning : imported.warnings) compiled.warnings.push_back({"", std::max(warning.line, 1), warning.message});
  if (!compiled.errors.empty()) return compiled;
  compiled.document = nlohmann::json::parse(imported.scenario.dump());
  adopt(load_scenario(compiled.document, options.load));
  return compiled;
}

nlohmann::json summarize(const Model& model) {
  int humans = 0;
  nlohmann::json robots = nlohmann::json::array();
  for (const AgentDef& agent : model.agents) {
    if (agent.kind == AgentKind::human) {
      ++humans;
    } else {
      robots.push_back({{"id", agent.id}, {"model", agent.robot_model ? nlohmann::json(agent.robot_model->name) : nlohmann::json()}});
    }
  }
  return {{"name", model.name},
          {"description", model.description},
          {"humans", humans},
          {"robots", robots},
          {"task", nullptr},
          {"duration", model.time_limit},
          {"steps", model.steps.size()},
          {"dt", model.dt}};
}

}  // namespace hrisim::scenario
