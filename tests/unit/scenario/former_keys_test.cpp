// The routine's former keys ("tasks", and "task" where a routine is named): read for one version more,
// with a warning at each; both names at one place are an error; every pointer said is one into the
// document as written; `hrisim import --upgrade` renames them in the text and touches nothing else.
#include "scenario/former_keys.hpp"

#include <gtest/gtest.h>

#include "scenario/load.hpp"
#include "support/scenarios.hpp"

namespace hrisim::scenario {
namespace {

using nlohmann::json;
using testing::room_scenario;
using testing::with_former_keys;

const json kRoutines = json::parse(R"({
  "locations": {"door": {"x": 1, "y": 1, "theta": 1.57}},
  "humans": [{"id": "ana", "start": {"x": 2, "y": 2}}, {"id": "ben", "start": {"x": 3, "y": 2}}],
  "robots": [{"id": "robot", "start": {"x": 2, "y": 8}}],
  "routines": {"fetch": [{"goto": {"location": "door"}}, {"routine": "pause"}], "pause": [{"wait": {"duration": 1}}]},
  "steps": [{"name": "go", "actions": [{"agent": "ana", "routine": "fetch"}, {"agent": "robot", "request": {"routine": "fetch"}}]}],
  "async": [{"routine": "fetch"}],
  "requests": [{"time": 3, "routine": "fetch"}]
})");

std::vector<std::string> pointers(const std::vector<core::ValidationError>& issues) {
  std::vector<std::string> found;
  for (const core::ValidationError& issue : issues) found.push_back(issue.pointer);
  return found;
}

/// An action as text: what a session does with it.
std::string described(const Action& action) {
  return std::to_string(static_cast<int>(action.kind)) + " agent " + std::to_string(action.agent) + " group " + std::to_string(action.group) +
         " target " + std::to_string(action.target) + (action.repeat ? " repeat" : "") + " at " + action.pointer;
}

std::vector<std::string> described(const Model& model) {
  std::vector<std::string> lines;
  for (const Routine& routine : model.routines) {
    for (const Action& action : routine.actions) lines.push_back(routine.name + ": " + described(action));
  }
  for (const Step& step : model.steps) {
    for (const Action& action : step.actions) lines.push_back(step.name + ": " + described(action));
  }
  for (const int routine : model.async_routines) lines.push_back("async " + model.routines[routine].name);
  for (const Request& request : model.requests) {
    lines.push_back("request " + model.routines[request.routine].name + " by " + std::to_string(request.robot) + " at " + std::to_string(request.time));
  }
  return lines;
}

TEST(FormerKeys, LoadAsTheCurrentOnesWithAWarningAtEach) {
  const LoadResult current = load_scenario(room_scenario(kRoutines), {});
  ASSERT_TRUE(current.model);
  EXPECT_TRUE(current.warnings.empty());
  const LoadResult former = load_scenario(with_former_keys(room_scenario(kRoutines)), {});
  for (const auto& error : former.errors) ADD_FAILURE() << error.pointer << ": " << error.message;
  ASSERT_TRUE(former.model);
  EXPECT_EQ(pointers(former.warnings), (std::vector<std::string>{"/tasks", "/tasks/fetch/1/task", "/steps/0/actions/0/task",
                                                                 "/steps/0/actions/1/request/task", "/async/0/task", "/requests/0/task"}));
  EXPECT_EQ(former.warnings[0].message,
            "'tasks' is the former name of 'routines' and will stop being read in the next version; run `hrisim import --upgrade FILE`");
  EXPECT_EQ(former.warnings[1].message,
            "'task' is the former name of 'routine' and will stop being read in the next version; run `hrisim import --upgrade FILE`");
  EXPECT_EQ(described(*former.model), described(*current.model));
  EXPECT_EQ(former.model->routines[0].actions[1].pointer, "/routines/fetch/1") << "the model says the current keys";
}

TEST(FormerKeys, WhatLoadingFindsIsSaidWhereTheDocumentHasIt) {
  json document = room_scenario(kRoutines);
  document["routines"]["fetch"][0]["agent"] = "ana";
  document["steps"][0]["actions"][0]["routine"] = "dance";
  document["routines"]["a"] = json::parse(R"([{"routine": "b"}])");
  document["routines"]["b"] = json::parse(R"([{"wait": {"duration": 1}}, {"routine": "a"}])");
  const LoadResult result = load_scenario(with_former_keys(document), {});
  EXPECT_FALSE(result.model);
  EXPECT_EQ(pointers(result.errors), (std::vector<std::string>{"/tasks/fetch/0/agent", "/steps/0/actions/0/task", "/tasks/b/1/task"}));
  EXPECT_EQ(result.errors[1].message, "unknown routine 'dance' (known: a, b, fetch, pause)");
  EXPECT_EQ(result.errors[2].message, "routine 'b' calls itself through 'a'");

  json listening = room_scenario(kRoutines);
  listening["routines"]["pause"] = json::parse(R"([{"wait": {"topic": "/bell", "message": "ring"}}])");
  const LoadResult warned = load_scenario(with_former_keys(listening), {});
  ASSERT_TRUE(warned.model);
  EXPECT_EQ(pointers(warned.warnings).back(), "/tasks/pause/0/wait") << warned.warnings.back().message;
}

TEST(FormerKeys, BothNamesAtOnePlaceAreAnError) {
  json both = with_former_keys(room_scenario(kRoutines));
  both["routines"] = both["tasks"];
  const LoadResult top = load_scenario(both, {});
  EXPECT_FALSE(top.model);
  ASSERT_FALSE(top.errors.empty());
  EXPECT_EQ(top.errors[0], (core::ValidationError{"/tasks", "'tasks' is the former name of 'routines', which is given here too: keep only 'routines'"}));

  json document = room_scenario(kRoutines);
  document["steps"][0]["actions"][0]["task"] = "pause";
  document["steps"][0]["actions"][1]["request"]["task"] = "fetch";
  document["async"][0]["task"] = "fetch";
  document["requests"][0]["task"] = "fetch";
  const LoadResult result = load_scenario(document, {});
  EXPECT_FALSE(result.model);
  EXPECT_EQ(pointers(result.errors), (std::vector<std::string>{"/steps/0/actions/0/task", "/steps/0/actions/1/request/task", "/async/0/task",
                                                               "/requests/0/task"}))
      << "the schema takes both, so that the error says which to keep";
  EXPECT_EQ(result.errors[0].message, "'task' is the former name of 'routine', which is given here too: keep only 'routine'");
}

TEST(FormerKeys, TheSchemaWantsOneOfTheNames) {
  json document = room_scenario(kRoutines);
  document["steps"][0]["actions"][1]["request"] = json::object();
  document["async"][0] = json::object();
  document["requests"][0].erase("routine");
  const LoadResult result = load_scenario(document, {});
  EXPECT_EQ(result.errors, (std::vector<core::ValidationError>{{"/async/0", "expected one of the forms: routine | task"},
                                                              {"/requests/0", "expected one of the forms: routine | task"},
                                                              {"/steps/0/actions/1/request", "expected one of the forms: routine | task"}}));
}

TEST(FormerKeys, PointersReadAsWritten) {
  const std::vector<FormerKey> keys = find_former_keys(with_former_keys(room_scenario(kRoutines)));
  EXPECT_EQ(pointer_as_written("/routines", keys), "/tasks");
  EXPECT_EQ(pointer_as_written("/routines/fetch/1/routine", keys), "/tasks/fetch/1/task");
  EXPECT_EQ(pointer_as_written("/steps/0/actions/1/request/routine", keys), "/steps/0/actions/1/request/task");
  EXPECT_EQ(pointer_as_written("/steps/0/actions/1/agent", keys), "/steps/0/actions/1/agent");
  EXPECT_EQ(pointer_as_written("/requests/0/routine", keys), "/requests/0/task");
  EXPECT_EQ(pointer_as_written("/world/walls/0", keys), "/world/walls/0");
  EXPECT_EQ(pointer_as_written("", keys), "");
}

TEST(FormerKeys, RenamedInTheTextWithEverythingElseAsItWas) {
  // Spacing, an escaped key, a "/" in a routine's name, numbers as written, the benchmark's task and a
  // step named "tasks": only the former keys change.
  const std::string text = "{\"name\": \"x\",\n"
                           "  \"t\\u0061sks\" : { \"a/b\": [ {\"task\":\"c\"} , {\"request\": {\"task\": \"c\"}} ] ,\"c\":[{\"wait\":{\"duration\":1.50}}]},\n"
                           "  \"task\": {\"name\": \"approach_human\"},\n"
                           "  \"steps\": [ {\"name\": \"tasks\", \"actions\": [{\"agent\": \"ana\", \"task\": \"a/b\", \"repeat\": true}]} ],\n"
                           "  \"async\":[{\"task\":\"c\"}],\"requests\":[{\"time\":1e0,\"task\":\"c\"}]\n"
                           "}\n";
  const std::string upgraded = "{\"name\": \"x\",\n"
                               "  \"routines\" : { \"a/b\": [ {\"routine\":\"c\"} , {\"request\": {\"routine\": \"c\"}} ] ,\"c\":[{\"wait\":{\"duration\":1.50}}]},\n"
                               "  \"task\": {\"name\": \"approach_human\"},\n"
                               "  \"steps\": [ {\"name\": \"tasks\", \"actions\": [{\"agent\": \"ana\", \"routine\": \"a/b\", \"repeat\": true}]} ],\n"
                               "  \"async\":[{\"routine\":\"c\"}],\"requests\":[{\"time\":1e0,\"routine\":\"c\"}]\n"
                               "}\n";
  const json document = json::parse(text);
  const std::vector<FormerKey> keys = find_former_keys(document);
  EXPECT_EQ(pointers([&] {
              std::vector<core::ValidationError> issues;
              for (const FormerKey& key : keys) issues.push_back(former_key_issue(key));
              return issues;
            }()),
            (std::vector<std::string>{"/tasks", "/tasks/a~1b/0/task", "/tasks/a~1b/1/request/task", "/steps/0/actions/0/task", "/async/0/task",
                                      "/requests/0/task"}));
  EXPECT_EQ(rename_former_keys(text, keys), upgraded);
  EXPECT_EQ(json::parse(upgraded), with_current_keys(document, keys));
  EXPECT_TRUE(find_former_keys(json::parse(upgraded)).empty());
}

TEST(FormerKeys, AnyJsonIsSearched) {
  for (const char* text : {"[]", "null", "\"tasks\"", R"({"tasks": 3, "steps": {"actions": 1}, "async": [1, {"task": []}], "requests": "x"})"}) {
    const std::vector<FormerKey> keys = find_former_keys(json::parse(text));
    EXPECT_EQ(keys.size(), std::string(text).starts_with("{") ? 2u : 0u) << text;
  }
}

}  // namespace
}  // namespace hrisim::scenario
