#include "http/request_contract.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "http/frames.hpp"
#include "http/router.hpp"
#include "http/session_limits.hpp"
#include "http/session_views.hpp"
#include "http/session_work.hpp"
#include "http/video_jobs.hpp"
#include "runs/labels.hpp"
#include "runs/spec.hpp"
#include "runs/video.hpp"

namespace hrisim::http {
namespace {

using nlohmann::json;

/// The value at `pointer` of the embedded OpenAPI (or, with "#asyncapi", AsyncAPI) description.
json described(const std::string& file, const std::string& pointer) {
  return json::parse(api_file(file)).at(json::json_pointer(pointer));
}

std::vector<core::ValidationError> errors_of(const core::JsonSchema* schema, const json& value) {
  if (schema == nullptr) throw std::runtime_error("no schema");
  return schema->validate(value);
}

TEST(RequestContract, EveryMessageASessionSocketAnswersHasItsSchema) {
  const RequestContract& contract = RequestContract::embedded();
  for (const char* type : {"step", "step_many", "commands", "snapshot", "restore", "seek", "state", "sensors", "laser", "audio", "camera", "scene", "subscribe"}) {
    EXPECT_NE(contract.message(type), nullptr) << type;
  }
  EXPECT_EQ(contract.message("subscribed"), nullptr) << "a message the server sends is not one it takes";
  EXPECT_EQ(contract.message("dance"), nullptr);
}

TEST(RequestContract, BodiesOfOtherMediaTypesAreLeftToTheirOwnChecks) {
  const RequestContract& contract = RequestContract::embedded();
  ASSERT_NE(contract.operation("POST", "/api/v1/sessions/{id}/step"), nullptr);
  EXPECT_NE(contract.operation("POST", "/api/v1/sessions/{id}/step")->body, nullptr);
  // A scenario upload (JSON, XML or YAML) is checked by the scenario schema, with its lines; an import is a database.
  ASSERT_NE(contract.operation("POST", "/api/v1/scenarios"), nullptr);
  EXPECT_EQ(contract.operation("POST", "/api/v1/scenarios")->body, nullptr);
  EXPECT_EQ(contract.operation("POST", "/api/v1/runs/import")->body, nullptr);
  EXPECT_EQ(contract.operation("GET", "/api/v1/sessions/{id}")->body, nullptr);
  EXPECT_EQ(contract.operation("GET", "/api/v1/nowhere"), nullptr);
}

TEST(RequestContract, TheDescribedLimitsAreTheServersNamedOnes) {
  // The schemas state the limits; the code still uses the same numbers by name (a seek's reach, a
  // query's size), so they must agree.
  const std::string step = "/components/schemas/StepRequest/properties/n/maximum";
  EXPECT_EQ(described("openapi.json", step), kMaxStepsPerRequest);
  const std::string many = "/paths/~1api~1v1~1sessions~1step/post/requestBody/content/application~1json/schema/properties/sessions/maxItems";
  EXPECT_EQ(described("openapi.json", many), kMaxSessionsPerStepMany);
  const std::string create = "/paths/~1api~1v1~1sessions/post/requestBody/content/application~1json/schema/properties/";
  EXPECT_EQ(described("openapi.json", create + "seed/maximum"), kMaxSeed);
  EXPECT_EQ(described("openapi.json", create + "realtime_factor/maximum"), kMaxRealtimeFactor);
  EXPECT_EQ(described("openapi.json", create + "unwatched_grace/maximum"), kMaxUnwatchedGrace.count());
  const std::string video = "/paths/~1api~1v1~1episodes~1{id}~1videos/post/requestBody/content/application~1json/schema/properties/";
  EXPECT_EQ(described("openapi.json", video + "fps/maximum"), runs::kMaxVideoFps);
  EXPECT_EQ(described("openapi.json", video + "fps/default"), runs::kDefaultVideoFps);
  EXPECT_EQ(described("openapi.json", video + "width/maximum"), kMaxVideoSide);
  EXPECT_EQ(described("openapi.json", "/components/schemas/RunRequest/properties/count/maximum"), runs::kMaxSeedsPerRun);
  EXPECT_EQ(described("openapi.json", "/components/schemas/RunLabels/properties/tags/maxItems"), runs::kMaxRunTags);
  EXPECT_EQ(described("asyncapi.json", "/components/messages/subscribe/payload/properties/rate/maximum"), kMaxPushRate);
  EXPECT_EQ(described("asyncapi.json", "/components/messages/camera/payload/properties/width/maximum"), kMaxFrameSize);
}

TEST(RequestContract, AMessageIsCheckedWithTheSchemasItsDescriptionRefersTo) {
  // asyncapi.yaml's step refers to openapi.yaml's StepRequest for its action.
  const core::JsonSchema* step = RequestContract::embedded().message("step");
  EXPECT_TRUE(errors_of(step, {{"type", "step"}, {"n", 3}, {"action", {0.1, 0.0}}}).empty());
  const auto errors = errors_of(step, {{"type", "step"}, {"n", 0}, {"action", {"fast"}}, {"speed", 1}});
  ASSERT_EQ(errors.size(), 3u);
  EXPECT_EQ(errors[0].pointer, "/action/0");
  EXPECT_EQ(errors[1].pointer, "/n");
  EXPECT_EQ(errors[2].pointer, "/speed");
}

TEST(RequestContract, ASchemaTheCheckerCannotReadStopsTheServerAtStartUp) {
  const json openapi = json::parse(R"({"paths": {"/a": {"post": {"requestBody": {"content": {"application/json":
      {"schema": {"type": "object", "properties": {"when": {"type": "string", "format": "date-time"}}}}}}}}}})");
  const json asyncapi = json::parse(R"({"operations": {}})");
  EXPECT_THROW(RequestContract(openapi, asyncapi), core::Error) << "format would be checked by no one";
}

TEST(RequestContract, ARouterFollowingItChecksBodiesBeforeTheHandlerAndRefusesUndescribedRoutes) {
  const RequestContract contract(json::parse(R"({"paths": {"/a/{id}": {"post": {"requestBody": {"content": {"application/json":
      {"schema": {"type": "object", "required": ["n"], "additionalProperties": false, "properties": {"n": {"type": "integer", "minimum": 1}}}}}}},
      "get": {}}}})"),
                                 json::parse(R"({"operations": {}})"));
  Router router;
  router.follow(contract);
  int handled = 0;
  router.add("POST", "/a/{id}", [&](const Request& request) {
    ++handled;
    return Response::json(200, request.checked_body);
  });
  router.add("GET", "/a/{id}", [](const Request&) { return Response::json(200, nullptr); });
  EXPECT_THROW(router.add("DELETE", "/a/{id}", [](const Request&) { return Response::json(204, nullptr); }), core::Error);

  Request good;
  good.method = "POST";
  good.path = "/a/1";
  good.body = R"({"n": 2})";
  const Response answered = router.dispatch(good);
  EXPECT_EQ(answered.status, 200);
  EXPECT_EQ(json::parse(answered.body), json({{"n", 2}}));

  Request bad = good;
  bad.body = R"({"n": 0, "m": 1})";
  const Response refused = router.dispatch(bad);
  EXPECT_EQ(refused.status, 400);
  const json error = json::parse(refused.body)["error"];
  EXPECT_EQ(error["details"]["errors"], json::parse(R"x([{"pointer": "/m", "message": "unknown key 'm'; known keys: n"},
                                                        {"pointer": "/n", "message": "must be at least 1 (got 0)"}])x"));
  EXPECT_EQ(error["details"]["pointer"], "/m");
  EXPECT_EQ(error["message"], "/m: unknown key 'm'; known keys: n (and 1 more)");
  bad.body = "";
  EXPECT_EQ(json::parse(router.dispatch(bad).body)["error"]["details"]["pointer"], "/n") << "an empty body is an empty object";
  EXPECT_EQ(handled, 1) << "a refused body never reaches its handler";
}

}  // namespace
}  // namespace hrisim::http
