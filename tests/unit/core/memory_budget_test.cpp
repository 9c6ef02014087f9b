#include "core/memory_budget.hpp"

#include <gtest/gtest.h>

#include <utility>

namespace hrisim::core {
namespace {

TEST(MemoryBudget, LeasesGrowUpToTheCeilingTogetherAndGiveBackWhenTheyEnd) {
  MemoryBudget budget(1000);
  MemoryBudget::Lease first(&budget);
  {
    MemoryBudget::Lease second(&budget);
    EXPECT_TRUE(first.grow(600));
    EXPECT_FALSE(second.grow(401)) << "600 + 401 passes 1000";
    EXPECT_EQ(second.bytes(), 0u) << "a refused growth takes nothing";
    EXPECT_TRUE(second.grow(400));
    EXPECT_EQ(budget.used(), 1000u);
    EXPECT_FALSE(first.grow(1));
  }
  EXPECT_EQ(budget.used(), 600u) << "the second lease gave its 400 back";
  EXPECT_TRUE(first.grow(400));
  EXPECT_FALSE(first.grow(static_cast<std::size_t>(-1))) << "no overflow past the ceiling";
}

TEST(MemoryBudget, AMovedLeaseGivesBackOnceFromWhereItWasMovedTo) {
  MemoryBudget budget(100);
  MemoryBudget::Lease moved;
  {
    MemoryBudget::Lease lease(&budget);
    ASSERT_TRUE(lease.grow(70));
    moved = std::move(lease);
  }
  EXPECT_EQ(budget.used(), 70u) << "the moved-from lease holds nothing";
  EXPECT_EQ(moved.bytes(), 70u);
  MemoryBudget::Lease other(&budget);
  ASSERT_TRUE(other.grow(30));
  moved = std::move(other);  // the 70 are given back, the 30 change hands
  EXPECT_EQ(budget.used(), 30u);
}

TEST(MemoryBudget, ALeaseWithoutBudgetAlwaysGrows) {
  MemoryBudget::Lease free;
  EXPECT_TRUE(free.grow(static_cast<std::size_t>(-1)));
}

}  // namespace
}  // namespace hrisim::core
