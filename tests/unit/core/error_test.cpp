#include "core/error.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <set>

namespace hrisim::core {
namespace {

TEST(Error, JsonCarriesCodeMessageAndDetails) {
  const Error error(ErrorCode::bad_request, "humans[3].start: inside obstacle \"sofa\"",
                    {{"pointer", "/humans/3/start"}});
  const nlohmann::json body = error.to_json();
  EXPECT_EQ(body["error"]["code"], "bad_request");
  EXPECT_EQ(body["error"]["message"], "humans[3].start: inside obstacle \"sofa\"");
  EXPECT_EQ(body["error"]["details"]["pointer"], "/humans/3/start");
}

TEST(Error, EmptyDetailsAreOmitted) {
  const nlohmann::json body = Error(ErrorCode::not_found, "no such episode").to_json();
  EXPECT_FALSE(body["error"].contains("details"));
}

TEST(Error, StatusesFollowHttpSemantics) {
  EXPECT_EQ(http_status(ErrorCode::bad_request), 400);
  EXPECT_EQ(http_status(ErrorCode::unauthorized), 401);
  EXPECT_EQ(http_status(ErrorCode::not_found), 404);
  EXPECT_EQ(http_status(ErrorCode::method_not_allowed), 405);
  EXPECT_EQ(http_status(ErrorCode::conflict), 409);
  EXPECT_EQ(http_status(ErrorCode::payload_too_large), 413);
  EXPECT_EQ(http_status(ErrorCode::headers_too_large), 431);
  EXPECT_EQ(http_status(ErrorCode::unavailable), 503);
  EXPECT_EQ(http_status(ErrorCode::storage), 500);
  EXPECT_EQ(http_status(ErrorCode::internal), 500);
}

TEST(Error, CodeNamesAreDistinct) {
  std::set<std::string_view> names;
  for (ErrorCode code : {ErrorCode::bad_request, ErrorCode::unauthorized, ErrorCode::not_found, ErrorCode::method_not_allowed,
                         ErrorCode::conflict, ErrorCode::payload_too_large, ErrorCode::headers_too_large,
                         ErrorCode::unavailable, ErrorCode::storage, ErrorCode::internal}) {
    names.insert(to_string(code));
  }
  EXPECT_EQ(names.size(), 10u);
}

}  // namespace
}  // namespace hrisim::core
