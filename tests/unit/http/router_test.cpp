#include "http/router.hpp"

#include <gtest/gtest.h>

namespace hrisim::http {
namespace {

Request get(const std::string& path, const std::string& method = "GET") {
  Request request;
  request.method = method;
  request.path = path;
  return request;
}

Router sample_router() {
  Router router;
  router.add("GET", "/api/v1/sessions/{id}", [](const Request& r) {
    return Response::json(200, {{"id", r.path_params.at("id")}});
  });
  router.add("DELETE", "/api/v1/sessions/{id}", [](const Request&) { return Response::json(204, nullptr); });
  router.add("GET", "/api/v1/boom", [](const Request&) -> Response { throw std::runtime_error("secret detail"); });
  router.add("GET", "/api/v1/conflict", [](const Request&) -> Response {
    throw core::Error(core::ErrorCode::conflict, "session is stepping");
  });
  router.add("POST", "/api/v1/parse", [](const Request& r) {
    return Response::json(200, nlohmann::json::parse(r.body));
  });
  return router;
}

TEST(Router, PathParametersAreCaptured) {
  const Response response = sample_router().dispatch(get("/api/v1/sessions/abc123"));
  EXPECT_EQ(response.status, 200);
  EXPECT_EQ(nlohmann::json::parse(response.body)["id"], "abc123");
}

TEST(Router, UnknownPathIs404Json) {
  const Response response = sample_router().dispatch(get("/api/v1/sessions"));
  EXPECT_EQ(response.status, 404);
  EXPECT_EQ(nlohmann::json::parse(response.body)["error"]["code"], "not_found");
}

TEST(Router, EmptySegmentDoesNotMatchAParameter) {
  EXPECT_EQ(sample_router().dispatch(get("/api/v1/sessions/")).status, 404);
}

TEST(Router, WrongMethodIs405WithAllow) {
  const Response response = sample_router().dispatch(get("/api/v1/sessions/x", "PUT"));
  EXPECT_EQ(response.status, 405);
  ASSERT_EQ(response.headers.size(), 1u);
  EXPECT_EQ(response.headers[0].first, "Allow");
  EXPECT_EQ(response.headers[0].second, "GET, DELETE");
}

TEST(Router, HeadIsAnsweredByGet) { EXPECT_EQ(sample_router().dispatch(get("/api/v1/sessions/x", "HEAD")).status, 200); }

TEST(Router, HandlerErrorsBecomeJsonErrors) {
  const Router router = sample_router();
  const Response conflict = router.dispatch(get("/api/v1/conflict"));
  EXPECT_EQ(conflict.status, 409);
  EXPECT_EQ(nlohmann::json::parse(conflict.body)["error"]["message"], "session is stepping");

  const Response internal = router.dispatch(get("/api/v1/boom"));
  EXPECT_EQ(internal.status, 500);
  EXPECT_EQ(internal.body.find("secret detail"), std::string::npos) << "internal details must not leak";
}

TEST(Router, MalformedJsonBodyIs400) {
  Request request = get("/api/v1/parse", "POST");
  request.body = "{\"a\": ";
  const Response response = sample_router().dispatch(request);
  EXPECT_EQ(response.status, 400);
  EXPECT_EQ(nlohmann::json::parse(response.body)["error"]["code"], "bad_request");
}

TEST(Router, FallbackAnswersUnmatchedPaths) {
  Router router = sample_router();
  router.set_fallback([](const Request& r) { return Response{200, "text/plain", "fallback " + r.path, {}, {}}; });
  EXPECT_EQ(router.dispatch(get("/index.html")).body, "fallback /index.html");
}

TEST(PercentDecode, DecodesAndRejectsMalformedEscapes) {
  EXPECT_EQ(percent_decode("/a%20b/%2e%2E"), "/a b/..");
  EXPECT_EQ(percent_decode("/plain"), "/plain");
  EXPECT_THROW(percent_decode("/bad%2"), core::Error);
  EXPECT_THROW(percent_decode("/bad%zz"), core::Error);
  EXPECT_THROW(percent_decode("/nul%00"), core::Error);
}

}  // namespace
}  // namespace hrisim::http
