#include "core/json_writer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <vector>

namespace hrisim::core {
namespace {

using nlohmann::json;

TEST(JsonWriter, NestedObjectsAndArraysParseAsWritten) {
  JsonWriter out;
  const std::vector<double> observation{0.5, -2.0, 1e-7};
  out.begin_object().key("id").value("s1").key("tick").value(std::int64_t{42}).key("running").value(true).key("end").null();
  out.key("observation").value(std::span<const double>(observation));
  out.key("nested").begin_array().begin_object().key("a").value(1).end_object().begin_array().end_array().end_array();
  out.key("tree").value(json{{"x", 1.5}, {"list", {1, 2}}});
  out.end_object();
  const json parsed = json::parse(out.text());
  EXPECT_EQ(parsed, (json{{"id", "s1"}, {"tick", 42}, {"running", true}, {"end", nullptr}, {"observation", observation},
                          {"nested", json::array({json{{"a", 1}}, json::array()})}, {"tree", {{"x", 1.5}, {"list", {1, 2}}}}}));
}

TEST(JsonWriter, DoublesRoundTripExactlyAndStayDoubles) {
  const std::vector<double> numbers{0.1, 1.0 / 3.0, -0.0, 100.0, 1e300, 5e-324, 123456789.125, -1e-5, 4e16};
  for (const double number : numbers) {
    JsonWriter out;
    out.value(number);
    const json parsed = json::parse(out.text());
    ASSERT_TRUE(parsed.is_number_float()) << out.text();
    EXPECT_EQ(std::bit_cast<std::uint64_t>(parsed.get<double>()), std::bit_cast<std::uint64_t>(number)) << out.text();
  }
  JsonWriter integral;
  integral.value(100.0);
  EXPECT_EQ(integral.text(), "100.0");
}

TEST(JsonWriter, NonFiniteNumbersAreNullAsNlohmannWritesThem) {
  for (const double number : {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), std::nan("")}) {
    JsonWriter out;
    out.begin_array().value(number).end_array();
    EXPECT_EQ(out.text(), json::array({number}).dump());
  }
}

TEST(JsonWriter, StringsAreEscapedAndInvalidUtf8IsReplaced) {
  const std::string tricky = "quote \" backslash \\ newline \n tab \t bell \x07 unicode \xc3\xa9";
  JsonWriter out;
  out.value(tricky);
  EXPECT_EQ(json::parse(out.text()).get<std::string>(), tricky);
  EXPECT_EQ(out.text(), json(tricky).dump());
  JsonWriter broken;
  broken.value(std::string("a\xff" "b"));
  EXPECT_EQ(json::parse(broken.text()).get<std::string>(), "a\xef\xbf\xbd" "b");
}

TEST(JsonWriter, MembersOfATreeJoinTheObjectBeingWritten) {
  JsonWriter out;
  out.begin_object().key("tick").value(3).members(json{{"reward", 0.5}, {"progress", -1}}).end_object();
  EXPECT_EQ(json::parse(out.text()), (json{{"tick", 3}, {"reward", 0.5}, {"progress", -1}}));
}

}  // namespace
}  // namespace hrisim::core
