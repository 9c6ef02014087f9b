#include "humans/recorded_trajectories.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.hpp"

namespace hrisim::humans {
namespace {

const std::string kFixture = std::string(HRISIM_SOURCE_DIR) + "/tests/fixtures/trajectories/passing.txt";

RecordedTrajectories read(const std::string& text, const RecordedLimits& limits = {}) {
  std::istringstream input(text);
  return read_eth_ucy(input, "walk.txt", limits);
}

using MessageAndLine = std::pair<std::string, std::string>;

/// The message of the error reading `text` throws, and the line its details name.
MessageAndLine error_of(const std::string& text, const RecordedLimits& limits = {}) {
  try {
    read(text, limits);
  } catch (const core::Error& error) {
    EXPECT_EQ(error.code(), core::ErrorCode::bad_request);
    return {error.what(), error.details().value("line", "")};
  }
  return {"no error", ""};
}

TEST(RecordedTrajectories, ReadsTheFixtureByPersonAndFrame) {
  std::ifstream input(kFixture);
  ASSERT_TRUE(input) << kFixture;
  const RecordedTrajectories read = read_eth_ucy(input, kFixture);
  EXPECT_EQ(read.rows, 85u);
  ASSERT_EQ(read.tracks.size(), 4u);
  for (std::size_t t = 0; t < 4; ++t) EXPECT_EQ(read.tracks[t].person, static_cast<long long>(t + 1));
  EXPECT_EQ(read.tracks[0].samples.size(), 24u);
  EXPECT_EQ(read.tracks[0].samples[23].frame, 230);
  EXPECT_TRUE(read.tracks[0].samples[23].position.isApprox(Vec2(11.04, 20.0)));
  EXPECT_TRUE(read.tracks[2].samples[0].position.isApprox(Vec2(9.88, -0.4)));
  // Person 4 (spaces, frames written 0.0) is not annotated at frame 100.
  ASSERT_EQ(read.tracks[3].samples.size(), 21u);
  EXPECT_EQ(read.tracks[3].samples[9].frame, 90);
  EXPECT_EQ(read.tracks[3].samples[10].frame, 110);
}

TEST(RecordedTrajectories, OrdersRowsGivenInAnyOrderAndSkipsBlankLines) {
  const RecordedTrajectories read = ::hrisim::humans::read("20 7 1 0\r\n\n  \n0\t7\t0.5\t0\r\n10 3 2 2\n10 7 0.75 0");  // no final newline
  EXPECT_EQ(read.rows, 4u);
  ASSERT_EQ(read.tracks.size(), 2u);
  EXPECT_EQ(read.tracks[0].person, 3);
  ASSERT_EQ(read.tracks[1].samples.size(), 3u);
  EXPECT_EQ(read.tracks[1].samples[0].frame, 0);
  EXPECT_EQ(read.tracks[1].samples[1].position, Vec2(0.75, 0.0));
  EXPECT_EQ(read.tracks[1].samples[2].frame, 20);
}

TEST(RecordedTrajectories, AFieldThatIsNotANumberIsAnErrorAtItsLine) {
  EXPECT_EQ(error_of("0 1 0.5 1\n10 1 0.5 north\n"), MessageAndLine("walk.txt:2: y 'north' is not a number", "2"));
  EXPECT_EQ(error_of("0 1 0.5 1\n\n10 1 nan 1\n").first, "walk.txt:3: x 'nan' is not a number");
  EXPECT_EQ(error_of("0x10 1 0 1\n").first, "walk.txt:1: frame '0x10' is not a number");
  EXPECT_EQ(error_of("0 1 1e400 1\n").first, "walk.txt:1: x '1e400' is not a number");
  EXPECT_EQ(error_of("0 1.5 0 1\n").first, "walk.txt:1: person '1.5' is not a whole number");
  EXPECT_EQ(error_of("0 1 200000 1\n").first, "walk.txt:1: x 200000 m is farther than 100000 m from the origin");
}

TEST(RecordedTrajectories, ARowWithoutFourFieldsIsAnErrorAtItsLine) {
  EXPECT_EQ(error_of("0 1 0.5 1\n10 1 0.5\n").first, "walk.txt:2: expected 4 fields (frame, person, x, y), found 3");
  EXPECT_EQ(error_of("0,1,0.5,1\n").first, "walk.txt:1: expected 4 fields (frame, person, x, y), found 1");
  EXPECT_EQ(error_of("0 1 0.5 1 0\n").first, "walk.txt:1: expected 4 fields (frame, person, x, y), found 5");
}

TEST(RecordedTrajectories, APersonTwiceInAFrameIsAnErrorAtTheSecondLine) {
  EXPECT_EQ(error_of("0 1 0 0\n0 2 5 5\n0 1.0 0.1 0\n"),
            MessageAndLine("walk.txt:3: person 1 is in frame 0 twice (also at line 1)", "3"));
}

TEST(RecordedTrajectories, AFilePastItsBoundsIsAnErrorAtTheLineThatGoesPast) {
  EXPECT_EQ(error_of("0 1 0 0\n\n10 1 0 0\n20 1 0 0\n", {.max_rows = 2}).first, "walk.txt:4: more than 2 rows");
  EXPECT_EQ(error_of("0 1 0 0\n0 2 0 0\n10 1 0 0\n10 3 0 0\n", {.max_people = 2}).first, "walk.txt:4: more than 2 people");
  EXPECT_EQ(error_of("50 1 0 0\n0 1 0 0\n150 1 0 0\n", {.max_frame_span = 100}).first, "walk.txt:3: frames 0 to 150 span more than 100");
  EXPECT_EQ(error_of("0 1 0 0\n0 2 0 0" + std::string(300, ' ') + "\n").first,
            "walk.txt:2: longer than 200 characters: not a row of four numbers");
  // The bounds count rows, not bytes: padding within a line's length is read.
  EXPECT_EQ(read("0 1 0 0" + std::string(150, ' ') + "\n", {.max_rows = 1}).rows, 1u);
}

}  // namespace
}  // namespace hrisim::humans
