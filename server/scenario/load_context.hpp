#pragma once
// What the native format's readers share (internal to the scenario module): JSON helpers, the names
// declared so far, and the errors, each at its JSON pointer.
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "scenario/model.hpp"

namespace hrisim::scenario::loading {

using nlohmann::json;
using Errors = std::vector<core::ValidationError>;

/// The member, or an empty value when absent (a reference that stays valid, unlike json::value()).
const json& member(const json& object, const char* key);
inline Pose2 read_pose(const json& j) { return {j.at("x").get<double>(), j.at("y").get<double>(), j.value("theta", 0.0)}; }
inline Vec2 read_point(const json& j) { return {j.at(0).get<double>(), j.at(1).get<double>()}; }

/// Names of everything the scenario declares, for resolving references.
struct Names {
  std::map<std::string, int> locations, social_spaces, queues, agents, routines, doors, groups;
  std::set<std::string> robots;
};

class Context {
 public:
  explicit Context(Errors& errors) : errors_(errors) {}

  Names names;

  void error(const std::string& pointer, const std::string& message) { errors_.push_back({pointer, message}); }
  /// The index `name` has in `table`, or -1 and an error at `pointer` listing the names known.
  int resolve(const std::map<std::string, int>& table, const std::string& name, const std::string& pointer, const std::string& what);
  /// Agents of a list, each once; errors for unknown and repeated ones.
  std::vector<int> members_of(const json& list, const std::string& pointer);
  /// Errors when p is outside the map or inside an obstacle, naming the obstacle when one contains it.
  void check_free(const Model& model, const Vec2& p, const std::string& pointer, const std::string& what);

 private:
  Errors& errors_;
};

}  // namespace hrisim::scenario::loading
