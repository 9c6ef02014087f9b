#include "runs/labels.hpp"

#include <algorithm>

namespace hrisim::runs {

nlohmann::json label_problems(const std::string& name, const std::vector<std::string>& tags, const std::string& notes) {
  nlohmann::json problems = nlohmann::json::array();
  const auto problem = [&](std::string pointer, std::string message) { problems.push_back({{"pointer", std::move(pointer)}, {"message", std::move(message)}}); };
  const auto text = [&](const char* key, const std::string& value, std::size_t most) {
    if (value.size() > most || value.find('\0') != std::string::npos) {
      problem(std::string("/") + key, std::string(key) + " must be text of at most " + std::to_string(most) + " bytes, without NUL");
    }
  };
  text("name", name, kMaxRunNameLength);
  text("notes", notes, kMaxRunNotesLength);
  if (tags.size() > kMaxRunTags) {
    problem("/tags", "tags must be a list of at most " + std::to_string(kMaxRunTags) + " words");
    return problems;
  }
  for (std::size_t i = 0; i < tags.size(); ++i) {
    const std::string& word = tags[i];
    const bool plain = !word.empty() && word.size() <= kMaxRunTagLength && word.find_first_of(std::string(", \t\r\n\0", 6)) == std::string::npos;
    if (!plain) {
      problem("/tags/" + std::to_string(i), "a tag is a word of 1 to " + std::to_string(kMaxRunTagLength) + " bytes without spaces or commas");
    } else if (std::find(tags.begin(), tags.begin() + static_cast<std::ptrdiff_t>(i), word) != tags.begin() + static_cast<std::ptrdiff_t>(i)) {
      problem("/tags/" + std::to_string(i), "tag '" + word + "' is given twice");
    }
  }
  return problems;
}

}  // namespace hrisim::runs
