#include "app/command_line.hpp"

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "runs/spec.hpp"
#include "scenario/import.hpp"

namespace hrisim::app {
namespace {

void print_messages(const std::string& file, const char* kind, const std::vector<scenario::ImportMessage>& messages) {
  for (const auto& message : messages) {
    std::fprintf(stderr, "%s:%s %s%s\n", file.c_str(), message.line > 0 ? (std::to_string(message.line) + ":").c_str() : "",
                 kind, message.message.c_str());
  }
}

}  // namespace

[[noreturn]] void usage_error(const std::string& message) {
  throw core::Error(core::ErrorCode::bad_request, message);
}

double parse_seconds(const std::string& option, const std::string& text) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !(value >= 0.0)) {
    usage_error(option + ": expected a number of seconds >= 0, got '" + text + "'");
  }
  return value;
}

ParsedArgs parse_args(const std::vector<std::string>& args, const std::set<std::string>& valued,
                      const std::set<std::string>& flags, const std::string& usage, bool many_files) {
  ParsedArgs parsed;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "--help" || arg == "-h") {
      std::printf("%s\n", usage.c_str());
      std::exit(0);
    }
    if (valued.contains(arg)) {
      if (i + 1 >= args.size()) usage_error(arg + " needs a value");
      parsed.values[arg].push_back(args[++i]);
    } else if (flags.contains(arg)) {
      parsed.flags.insert(arg);
    } else if (arg.starts_with("--")) {
      usage_error("unknown option " + arg);
    } else if (parsed.file.empty() || many_files) {
      if (parsed.file.empty()) parsed.file = arg;
      parsed.files.push_back(arg);
    } else {
      usage_error("unexpected argument '" + arg + "'");
    }
  }
  if (parsed.file.empty()) usage_error(usage);
  return parsed;
}

SourceOptions source_options(const ParsedArgs& parsed) {
  SourceOptions source;
  source.format = parsed.last("--from").value_or("");
  if (!source.format.empty() && source.format != "imhus" && source.format != "pedsim" && source.format != "hunav") {
    usage_error("--from: expected imhus, pedsim or hunav, got '" + source.format + "'");
  }
  source.dialect = parsed.last("--dialect").value_or("");
  if (!source.dialect.empty() && source.dialect != "pedsim_ros" && source.dialect != "libpedsim") {
    usage_error("--dialect: expected pedsim_ros or libpedsim, got '" + source.dialect + "'");
  }
  source.scenario = parsed.last("--scenario").value_or("");
  if (const auto map = parsed.last("--map")) source.map = *map;
  return source;
}

/// A file's format: --from's, else its extension's (.json, .xml: IMHuS or Pedsim by the content,
/// .yaml/.yml: HuNavSim), else its content's.
scenario::SourceFormat file_format(const std::string& file, std::string_view text, const SourceOptions& source) {
  if (!source.format.empty()) return *scenario::source_format(source.format);
  const std::string extension = std::filesystem::path(file).extension().string();
  if (extension == ".json") return scenario::SourceFormat::json;
  if (extension == ".yaml" || extension == ".yml") return scenario::SourceFormat::hunav_yaml;
  if (extension == ".xml") return scenario::detect_xml_format(text) == "pedsim" ? scenario::SourceFormat::pedsim_xml : scenario::SourceFormat::imhus_xml;
  return scenario::detect_source_format(text);
}

std::optional<std::string> read_text(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Imports an IMHuS or Pedsim XML file or a HuNavSim agents file; prints its warnings, and its errors
/// when there are any.
std::optional<scenario::ImportResult> import_file(const std::string& file, const std::string& text, scenario::SourceFormat format,
                                                  const SourceOptions& source) {
  scenario::ImportOptions options{source.scenario, source.map, {std::filesystem::path(file).parent_path(), bundled_scenarios_dir()},
                                  std::filesystem::path(file).filename().string(), {}, source.dialect};
  options.limits.confine_files = false;  // a user's own files, on their own machine
  scenario::ImportResult result = format == scenario::SourceFormat::imhus_xml    ? scenario::import_imhus(text, options)
                                  : format == scenario::SourceFormat::pedsim_xml ? scenario::import_pedsim(text, options)
                                                                                 : scenario::import_hunav(text, options);
  print_messages(file, "warning: ", result.warnings);
  if (!result.errors.empty()) {
    print_messages(file, "", result.errors);
    return std::nullopt;
  }
  return result;
}

LoadedFile load(const std::string& file, const SourceOptions& source) {
  LoadedFile loaded;
  loaded.load = {{std::filesystem::path(file).parent_path(), bundled_scenarios_dir()}, {}};
  loaded.load.limits.confine_files = false;  // a user's own files, on their own machine
  auto text = read_text(file);
  if (!text) {
    loaded.result.errors = {{"", "cannot read the file"}};
    return loaded;
  }
  loaded.text = std::move(*text);
  loaded.format = file_format(file, loaded.text, source);
  if (loaded.format == scenario::SourceFormat::json) {
    loaded.result = scenario::load_scenario_text(loaded.text, loaded.load);
    if (loaded.result.model) loaded.document = nlohmann::json::parse(loaded.text);
    return loaded;
  }
  const auto imported = import_file(file, loaded.text, loaded.format, source);
  if (!imported) {
    loaded.result.errors = {{"", "the file could not be imported"}};
    return loaded;
  }
  loaded.document = imported->scenario;
  loaded.result = scenario::load_scenario(loaded.document, loaded.load);
  loaded.imported = imported;
  return loaded;
}

/// Errors as `FILE: POINTER: message`; for an imported file `FILE:LINE: POINTER: message`, at the XML
/// line the part at fault came from.
void print_errors(const std::string& file, const std::vector<core::ValidationError>& errors, const char* kind,
                  const scenario::ImportResult* imported) {
  for (const auto& error : errors) {
    const int line = imported ? scenario::origin_line(*imported, error.pointer) : 0;
    std::fprintf(stderr, "%s:%s %s: %s%s\n", file.c_str(), line > 0 ? (std::to_string(line) + ":").c_str() : "",
                 error.pointer.empty() ? "(document)" : error.pointer.c_str(), kind, error.message.c_str());
  }
}

void print_errors(const std::string& file, const LoadedFile& loaded) {
  print_errors(file, loaded.result.errors, "", loaded.imported ? &*loaded.imported : nullptr);
}

std::string bundled_scenarios_dir() {
  const char* configured = std::getenv("HRISIM_SCENARIOS");
  return configured ? configured : "scenarios";
}

/// Seeds of `--seeds`: "A-B" (inclusive) or "A,B,C".
std::vector<std::uint64_t> parse_seeds(const std::string& text) {
  auto number = [&](std::string_view part) {
    std::uint64_t value = 0;
    const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), value);
    if (ec != std::errc() || end != part.data() + part.size()) usage_error("--seeds: expected A-B or A,B,C of whole numbers, got '" + text + "'");
    return value;
  };
  std::vector<std::uint64_t> seeds;
  if (text.empty()) usage_error("--seeds: expected A-B or A,B,C of whole numbers, got nothing");
  if (const auto dash = text.find('-'); dash != std::string::npos) {
    const std::uint64_t first = number(std::string_view(text).substr(0, dash)), last = number(std::string_view(text).substr(dash + 1));
    if (last < first || last - first >= runs::kMaxSeedsPerRun) {
      usage_error("--seeds: A-B needs A <= B and at most " + std::to_string(runs::kMaxSeedsPerRun) + " seeds, got '" + text + "'");
    }
    for (std::uint64_t seed = first; seed <= last; ++seed) seeds.push_back(seed);
  } else {
    std::string_view rest(text);
    while (!rest.empty()) {
      const auto comma = rest.find(',');
      seeds.push_back(number(rest.substr(0, comma)));
      rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
    }
  }
  return seeds;
}

}  // namespace hrisim::app
