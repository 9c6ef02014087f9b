#include "scenario/former_keys.hpp"

#include <map>

namespace hrisim::scenario {
namespace {

using nlohmann::json;

class Finder {
 public:
  explicit Finder(std::vector<FormerKey>& found) : found_(found) {}

  void key(const json& object, const std::string& parent, const char* former, const char* current) {
    if (object.is_object() && object.contains(former)) found_.push_back({parent, former, current, object.contains(current)});
  }

  /// A step's or a routine's actions: performing a routine, and a robot's request for one.
  void actions(const json& list, const std::string& pointer) {
    if (!list.is_array()) return;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string action = pointer + "/" + std::to_string(i);
      key(list[i], action, "task", "routine");
      if (list[i].is_object() && list[i].contains("request")) key(list[i]["request"], action + "/request", "task", "routine");
    }
  }

 private:
  std::vector<FormerKey>& found_;
};

}  // namespace

std::vector<FormerKey> find_former_keys(const json& document) {
  std::vector<FormerKey> found;
  if (!document.is_object()) return found;
  Finder finder(found);
  finder.key(document, "", "tasks", "routines");
  for (const char* routines : {"tasks", "routines"}) {
    const auto named = document.find(routines);
    if (named == document.end() || !named->is_object()) continue;
    for (const auto& [name, actions] : named->items()) finder.actions(actions, std::string("/") + routines + "/" + core::pointer_token(name));
  }
  if (const auto steps = document.find("steps"); steps != document.end() && steps->is_array()) {
    for (std::size_t s = 0; s < steps->size(); ++s) {
      const json& step = (*steps)[s];
      if (step.is_object() && step.contains("actions")) finder.actions(step["actions"], "/steps/" + std::to_string(s) + "/actions");
    }
  }
  for (const char* section : {"async", "requests"}) {
    const auto list = document.find(section);
    if (list == document.end() || !list->is_array()) continue;
    for (std::size_t i = 0; i < list->size(); ++i) finder.key((*list)[i], std::string("/") + section + "/" + std::to_string(i), "task", "routine");
  }
  return found;
}

core::ValidationError former_key_issue(const FormerKey& key) {
  if (key.current_too) {
    return {key.pointer(), "'" + key.former + "' is the former name of '" + key.current + "', which is given here too: keep only '" + key.current + "'"};
  }
  return {key.pointer(), "'" + key.former + "' is the former name of '" + key.current +
                             "' and will stop being read in the next version; run `hrisim import --upgrade FILE`"};
}

json with_current_keys(json document, const std::vector<FormerKey>& keys) {
  // The keys inside a renamed "tasks" first, while their parents' pointers still hold.
  for (auto key = keys.rbegin(); key != keys.rend(); ++key) {
    json& object = document.at(json::json_pointer(key->parent));
    object[key->current] = std::move(object[key->former]);
    object.erase(key->former);
  }
  return document;
}

std::string pointer_as_written(std::string_view pointer, const std::vector<FormerKey>& keys) {
  std::string written;
  std::size_t start = 0;
  while (start < pointer.size()) {  // each "/token", the document's own words put back in turn
    const std::size_t end = pointer.find('/', start + 1);
    std::string_view token = pointer.substr(start + 1, end == std::string_view::npos ? std::string_view::npos : end - start - 1);
    for (const FormerKey& key : keys) {
      if (key.parent == written && key.current == token) {
        token = key.former;
        break;
      }
    }
    written.append("/").append(token);
    start = end == std::string_view::npos ? pointer.size() : end;
  }
  return written;
}

std::string rename_former_keys(std::string_view text, const std::vector<FormerKey>& keys) {
  std::map<std::string, std::string, std::less<>> renamed;  // a former key's pointer → its current name
  for (const FormerKey& key : keys) renamed[key.pointer()] = key.current;
  // The text's structure walked by its brackets, commas and strings, with the pointer of each
  // container open and of the member whose value comes next; a key found in `renamed` is replaced
  // and the bytes between replacements are copied as they are.
  struct Open {
    std::string pointer;
    bool object = false;
    std::size_t index = 0;  ///< an array's: its element being read
  };
  std::vector<Open> open;
  std::string out, member;
  std::size_t copied = 0;
  bool key_next = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    switch (text[i]) {
      case '{':
      case '[': {
        std::string pointer = open.empty()         ? std::string()
                              : open.back().object ? member
                                                   : open.back().pointer + "/" + std::to_string(open.back().index);
        open.push_back({std::move(pointer), text[i] == '{'});
        key_next = text[i] == '{';
        break;
      }
      case '}':
      case ']':
        open.pop_back();
        key_next = false;
        break;
      case ',':
        if (open.back().object) {
          key_next = true;
        } else {
          ++open.back().index;
        }
        break;
      case '"': {
        std::size_t end = i + 1;
        while (text[end] != '"') end += text[end] == '\\' ? 2 : 1;
        if (key_next) {
          member = open.back().pointer + "/" + core::pointer_token(json::parse(text.substr(i, end + 1 - i)).get<std::string>());
          if (const auto found = renamed.find(member); found != renamed.end()) {
            out.append(text.substr(copied, i - copied)).append(json(found->second).dump());
            copied = end + 1;
          }
          key_next = false;
        }
        i = end;
        break;
      }
      default:
        break;
    }
  }
  return out.append(text.substr(copied));
}

}  // namespace hrisim::scenario
