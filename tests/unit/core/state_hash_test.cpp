// The state hasher: exact bits, order and every word count.
#include "core/state_hash.hpp"

#include <gtest/gtest.h>

#include <set>
#include <vector>

namespace hrisim::core {
namespace {

std::uint64_t hash_of(std::initializer_list<double> values) {
  StateHasher hash;
  for (const double value : values) hash.add(value);
  return hash.value();
}

TEST(StateHasher, EveryBitOfEveryWordAndTheirOrderCount) {
  const std::uint64_t base = hash_of({1.0, 2.0, 3.0});
  EXPECT_EQ(hash_of({1.0, 2.0, 3.0}), base);
  EXPECT_NE(hash_of({1.0, 3.0, 2.0}), base) << "order";
  EXPECT_NE(hash_of({1.0, 2.0}), base) << "length";
  EXPECT_NE(hash_of({-0.0}), hash_of({0.0})) << "the exact bits, not the value";
  // Flipping any single bit of any word gives a hash of its own.
  std::set<std::uint64_t> seen{base};
  const double values[] = {1.0, 2.0, 3.0};
  for (int word = 0; word < 3; ++word) {
    for (int bit = 0; bit < 64; ++bit) {
      StateHasher hash;
      for (int w = 0; w < 3; ++w) hash.add(w == word ? std::bit_cast<std::uint64_t>(values[w]) ^ (std::uint64_t{1} << bit) : std::bit_cast<std::uint64_t>(values[w]));
      EXPECT_TRUE(seen.insert(hash.value()).second) << "word " << word << " bit " << bit;
    }
  }
}

TEST(StateHasher, ABlockOfNumbersCountsEveryBitToo) {
  std::vector<double> scan(1081, 2.5);
  StateHasher whole;
  whole.add(std::span<const double>(scan));
  std::set<std::uint64_t> seen{whole.value()};
  for (const std::size_t at : {std::size_t{0}, std::size_t{540}, std::size_t{1080}}) {
    for (int bit = 0; bit < 64; ++bit) {
      std::vector<double> changed = scan;
      changed[at] = std::bit_cast<double>(std::bit_cast<std::uint64_t>(changed[at]) ^ (std::uint64_t{1} << bit));
      StateHasher hash;
      hash.add(std::span<const double>(changed));
      EXPECT_TRUE(seen.insert(hash.value()).second) << "value " << at << " bit " << bit;
    }
  }
  // Two values changed the same way (here both signs) do not cancel out.
  for (const auto& [i, j] : {std::pair{0, 1}, std::pair{3, 700}, std::pair{540, 1080}}) {
    std::vector<double> changed = scan;
    changed[i] = -changed[i];
    changed[j] = -changed[j];
    StateHasher hash;
    hash.add(std::span<const double>(changed));
    EXPECT_NE(hash.value(), whole.value()) << "values " << i << " and " << j;
  }
  StateHasher shorter;
  shorter.add(std::span<const double>(scan.data(), 1080));
  EXPECT_NE(shorter.value(), whole.value());
}

TEST(StateHasher, TextCountsByContentAndLength) {
  StateHasher a, b, c;
  a.add(std::string_view("ab")).add(std::string_view("c"));
  b.add(std::string_view("a")).add(std::string_view("bc"));
  c.add(std::string_view("ab")).add(std::string_view("c"));
  EXPECT_NE(a.value(), b.value());
  EXPECT_EQ(a.value(), c.value());
}

}  // namespace
}  // namespace hrisim::core
