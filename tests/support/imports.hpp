#pragma once
// What the importers' tests share: reading fixtures, the published files of ../shared/external (read in
// place when the project's checkout has ../shared beside it; a clone of the project alone skips their
// tests, and the project's own fixtures take the same importer paths), and checks of located messages.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "scenario/import.hpp"
#include "scenario/load.hpp"

namespace hrisim::testing {

inline const std::filesystem::path kFixtures = std::filesystem::path(HRISIM_SOURCE_DIR) / "tests/fixtures";
inline const std::filesystem::path kShared = HRISIM_SHARED_DIR;

inline std::string read(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The reason a test of a ../shared/external file gives for skipping when the file is not there.
inline std::string no_reference_file(const std::string& file, const std::string& covered_by) {
  return "no ../shared/external/" + file + " beside the project: the project's own fixture " + covered_by + " covers this path";
}

/// The imported scenario's model; every import or load error is a failure.
inline std::shared_ptr<const scenario::Model> load_imported(const scenario::ImportResult& imported, const scenario::LoadOptions& options = {}) {
  for (const auto& e : imported.errors) ADD_FAILURE() << "line " << e.line << ": " << e.message;
  const scenario::LoadResult loaded = scenario::load_scenario(nlohmann::json::parse(imported.scenario.dump()), options);
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.pointer << ": " << e.message;
  return loaded.model;
}

inline ::testing::AssertionResult has_message(const std::vector<scenario::ImportMessage>& messages, int line, const std::string& fragment) {
  for (const auto& m : messages) {
    if (m.line == line && m.message.find(fragment) != std::string::npos) return ::testing::AssertionSuccess();
  }
  std::string all;
  for (const auto& m : messages) all += "\n  " + std::to_string(m.line) + ": " + m.message;
  return ::testing::AssertionFailure() << "no message at line " << line << " with '" << fragment << "' in:" << all;
}

}  // namespace hrisim::testing
