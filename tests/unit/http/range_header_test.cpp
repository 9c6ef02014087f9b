// Range headers of file downloads (issue 40, finding 10: RFC 9110 §14.1–14.2).
#include "http/range_header.hpp"

#include <gtest/gtest.h>

namespace hrisim::http {
namespace {

using Kind = AskedRange::Kind;
constexpr std::uint64_t kLength = 1000;

void expect_part(std::string_view header, std::uint64_t first, std::uint64_t last) {
  const AskedRange asked = read_range_header(header, kLength);
  EXPECT_EQ(asked.kind, Kind::part) << header;
  EXPECT_EQ(asked.first, first) << header;
  EXPECT_EQ(asked.last, last) << header;
}

void expect_kind(std::string_view header, Kind kind, std::uint64_t length = kLength) {
  EXPECT_EQ(read_range_header(header, length).kind, kind) << header << " of " << length << " bytes";
}

TEST(RangeHeader, ValidRangesSelectTheirBytes) {
  expect_part("bytes=0-99", 0, 99);
  expect_part("bytes=100-", 100, 999);
  expect_part("bytes=-10", 990, 999);
  expect_part("bytes=-5000", 0, 999);
  expect_part("bytes=990-5000", 990, 999);
  expect_part("bytes=999-999", 999, 999);
  expect_part("bytes=0-99,", 0, 99);
  expect_part("bytes=0-99 ,", 0, 99);
  expect_part("bytes=0-18446744073709551616000", 0, 999);
}

TEST(RangeHeader, ASpaceAfterTheEqualsSignOrAPlusIsInvalidNotASuffix) {
  // Read as bytes from the end before: "bytes= 0-1" and "bytes=+1-2" returned the file's last bytes.
  expect_kind("bytes= 0-1", Kind::whole);
  expect_kind("bytes=+1-2", Kind::whole);
  expect_kind("bytes=-+1", Kind::whole);
  expect_kind("bytes=0x1-2", Kind::whole);
  expect_kind("bytes=1 -2", Kind::whole);
  expect_kind("bytes=1-2 x", Kind::whole);
  expect_kind("bytes=-", Kind::whole);
  expect_kind("bytes=", Kind::whole);
  expect_kind("bytes=,", Kind::whole);
}

TEST(RangeHeader, AnInvertedRangeIsIgnoredNot416) {
  // 416 before; RFC 9110 §14.1.1: an int-range whose last-pos is below its first-pos is invalid.
  expect_kind("bytes=5-3", Kind::whole);
  expect_kind("bytes=2000-1500", Kind::whole);
}

TEST(RangeHeader, TheUnitIsCaseInsensitive) {
  expect_part("BYTES=0-1", 0, 1);
  expect_part("Bytes=-1", 999, 999);
  expect_kind("items=0-1", Kind::whole);
  expect_kind("bytes =0-1", Kind::whole);
  expect_kind("bytes0-1", Kind::whole);
}

TEST(RangeHeader, SeveralRangesAreIgnoredRatherThanSentAsMultipart) {
  expect_kind("bytes=0-1,5-6", Kind::whole);
  expect_kind("bytes=0-1, 2000-", Kind::whole);
  expect_kind("bytes=0-1,5-3", Kind::whole);
}

TEST(RangeHeader, ARangePastTheEndIsUnsatisfiable) {
  expect_kind("bytes=1000-", Kind::unsatisfiable);
  expect_kind("bytes=1000-2000", Kind::unsatisfiable);
  expect_kind("bytes=18446744073709551616000-", Kind::unsatisfiable);
  expect_kind("bytes=-0", Kind::unsatisfiable);
  expect_kind("bytes=0-", Kind::unsatisfiable, 0);
  // A suffix of an empty file: nothing to select a part of, the (empty) whole is sent.
  expect_kind("bytes=-5", Kind::whole, 0);
}

}  // namespace
}  // namespace hrisim::http
