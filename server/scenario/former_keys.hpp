#pragma once
// Keys the scenario format renamed, still read for one version. One word, one meaning (issue 41): what
// a person performs, an IMHuS compound task, is a *routine* — "routines", an action's "routine", a
// request's, async's and requests' "routine" —, so that "task" means the benchmark's task only. A
// document with the former names loads as before, with a warning at each; `hrisim import --upgrade`
// renames them in the file.
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "core/json_schema.hpp"

namespace hrisim::scenario {

/// A former key where a document uses it.
struct FormerKey {
  std::string parent;        ///< the object that holds it: a JSON pointer into the document as written
  std::string former;        ///< "tasks" or "task"
  std::string current;       ///< "routines" or "routine"
  bool current_too = false;  ///< the object has the current key as well: an error
  std::string pointer() const { return parent + "/" + former; }
};

/// Every former key of `document`, a top-level "tasks" before the keys inside it. Any JSON value is
/// searched, not only one the schema accepts.
std::vector<FormerKey> find_former_keys(const nlohmann::json& document);

/// What a former key gets at its pointer: a warning naming its current name and
/// `hrisim import --upgrade`, or an error when the current key is there too.
core::ValidationError former_key_issue(const FormerKey& key);

/// `document` with `keys` (found in it, none with the current key too) renamed.
nlohmann::json with_current_keys(nlohmann::json document, const std::vector<FormerKey>& keys);

/// A pointer into the document with_current_keys made, as it reads in the document as written.
std::string pointer_as_written(std::string_view pointer, const std::vector<FormerKey>& keys);

/// `text`, valid JSON, with `keys` (found in its document) renamed and every other byte as it was:
/// spacing, the keys' order, numbers as written.
std::string rename_former_keys(std::string_view text, const std::vector<FormerKey>& keys);

}  // namespace hrisim::scenario
