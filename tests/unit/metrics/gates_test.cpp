// Gate expressions and the statistics they read.
#include "metrics/gates.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <iterator>
#include <set>
#include <vector>

#include "core/error.hpp"
#include "metrics/definitions.hpp"

namespace hrisim::metrics {
namespace {

TEST(Aggregate, MeanStdAndStudentInterval) {
  const std::vector<std::optional<double>> values{1.0, 2.0, std::nullopt, 3.0, 4.0};
  const Aggregate a = aggregate(values, false);
  EXPECT_EQ(a.count, 4);
  EXPECT_EQ(a.nulls, 1);
  EXPECT_EQ(*a.mean, 2.5);
  EXPECT_NEAR(*a.std, std::sqrt(5.0 / 3.0), 1e-12);
  EXPECT_EQ(*a.min, 1.0);
  EXPECT_EQ(*a.max, 4.0);
  // t(0.975, 3) = 3.182.
  EXPECT_NEAR(*a.ci95_low, 2.5 - 3.182 * std::sqrt(5.0 / 3.0) / 2, 1e-9);
  EXPECT_NEAR(*a.ci95_high, 2.5 + 3.182 * std::sqrt(5.0 / 3.0) / 2, 1e-9);
}

TEST(Aggregate, WilsonIntervalForRates) {
  std::vector<std::optional<double>> values(10, 1.0);
  values[0] = values[1] = 0.0;
  const Aggregate a = aggregate(values, true);
  EXPECT_NEAR(*a.mean, 0.8, 1e-12);
  // Wilson's score interval for 8 of 10 at 95 %.
  EXPECT_NEAR(*a.ci95_low, 0.4902, 1e-4);
  EXPECT_NEAR(*a.ci95_high, 0.9433, 1e-4);
}

TEST(Aggregate, EmptyAndSingleValues) {
  const Aggregate none = aggregate(std::vector<std::optional<double>>{std::nullopt}, false);
  EXPECT_EQ(none.count, 0);
  EXPECT_FALSE(none.mean);
  const Aggregate one = aggregate(std::vector<std::optional<double>>{2.0}, false);
  EXPECT_EQ(*one.mean, 2.0);
  EXPECT_FALSE(one.std) << "a spread needs two values";
  EXPECT_FALSE(one.ci95_low);
}

TEST(StudentT, TablesAndExpansionAgree) {
  EXPECT_NEAR(student_t95(1), 12.706, 1e-3);
  EXPECT_NEAR(student_t95(30), 2.042, 1e-3);
  EXPECT_NEAR(student_t95(40), 2.021, 1e-3);
  EXPECT_NEAR(student_t95(120), 1.980, 1e-3);
}

TEST(Gates, ParseTheDocumentedForms) {
  const Gate a = parse_gate("collisions.max == 0");
  EXPECT_EQ(a.metric, "collisions");
  EXPECT_EQ(a.statistic, "max");
  EXPECT_EQ(a.op, "==");
  EXPECT_EQ(a.threshold, 0.0);
  const Gate b = parse_gate("  minimum_distance_to_people.min>=0.3 ");
  EXPECT_EQ(b.op, ">=");
  EXPECT_EQ(b.threshold, 0.3);
  EXPECT_EQ(b.text, "minimum_distance_to_people.min>=0.3");
  EXPECT_EQ(parse_gate("success.mean < 1e-1").threshold, 0.1);
}

TEST(Gates, RefuseWhatTheyCannotEvaluate) {
  for (const char* text : {"", "collisions", "collisions.max", "speed.max < 1", "collisions.median == 0", "collisions.max = 0",
                           "collisions.max == ", "collisions.max == zero", "collisions.max == 1x", "collisions.max == inf"}) {
    EXPECT_THROW(parse_gate(text), core::Error) << text;
  }
  try {
    parse_gate("speed.max < 1");
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown metric 'speed'"), std::string::npos) << e.what();
  }
}

TEST(Gates, EvaluateEveryOperatorAndFailWithoutAValue) {
  Aggregate a;
  a.max = 2.0;
  EXPECT_TRUE(evaluate_gate(parse_gate("collisions.max == 2"), a).passed);
  EXPECT_FALSE(evaluate_gate(parse_gate("collisions.max != 2"), a).passed);
  EXPECT_TRUE(evaluate_gate(parse_gate("collisions.max <= 2"), a).passed);
  EXPECT_FALSE(evaluate_gate(parse_gate("collisions.max < 2"), a).passed);
  EXPECT_TRUE(evaluate_gate(parse_gate("collisions.max >= 2"), a).passed);
  EXPECT_FALSE(evaluate_gate(parse_gate("collisions.max > 2"), a).passed);
  const GateResult missing = evaluate_gate(parse_gate("collisions.mean == 0"), a);
  EXPECT_FALSE(missing.passed);
  EXPECT_FALSE(missing.actual);
}

TEST(Definitions, KeysAreUniqueAndTheReferencePageIsCurrent) {
  std::set<std::string_view> keys;
  for (const Definition& d : definitions()) {
    EXPECT_TRUE(keys.insert(d.key).second) << d.key;
    EXPECT_FALSE(d.unit.empty()) << d.key;
    EXPECT_FALSE(d.description.empty()) << d.key;
  }
  std::ifstream in(std::string(HRISIM_SOURCE_DIR) + "/docs/metrics.md");
  const std::string page((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(page, reference_markdown()) << "docs/metrics.md is stale: build/…/hrisim metrics > docs/metrics.md";
}

}  // namespace
}  // namespace hrisim::metrics
