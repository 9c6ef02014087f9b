// A results database from elsewhere, read the one way (storage::ForeignDatabase): a file of hrisim's
// is read whole well within its work budget, and left as it was.
#include "storage/foreign.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "core/error.hpp"
#include "storage/store.hpp"

namespace hrisim::storage {
namespace {

const std::filesystem::path kResults = std::filesystem::path(HRISIM_SOURCE_DIR) / "fuzz/corpus/import/two-shards-merged.db";

std::string bytes_of(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(ForeignDatabase, AResultsFileCostsAFractionOfItsBudget) {
  const std::string before = bytes_of(kResults);
  ForeignDatabase database = ForeignDatabase::from_file(kResults, "two-shards-merged.db");
  std::size_t episodes = 0;
  for (const RunRecord& run : database.store().all_runs()) {
    ASSERT_TRUE(database.store().scenario(run.scenario_id));
    for (const std::string& id : database.store().episode_ids_of_run(run.id)) {
      ASSERT_TRUE(database.store().episode(id));
      database.store().series(id);
      ++episodes;
    }
  }
  EXPECT_EQ(episodes, 2u);
  const double per_byte = static_cast<double>(database.work_spent()) / static_cast<double>(before.size());
  std::printf("checked, copied and read: %.2f steps a byte of %zu bytes, budget %llu steps\n", per_byte, before.size(),
              static_cast<unsigned long long>(database.work_budget()));
  EXPECT_LT(database.work_spent(), database.work_budget() / 10) << "a real file stays far within its budget";
  EXPECT_EQ(bytes_of(kResults), before) << "the file is only read";
}

TEST(ForeignDatabase, WhatIsNoDatabaseOrNoneOfHrisimsIsABadRequest) {
  for (const std::string& bytes : {std::string("not a database"), std::string("SQLite format 3\0 and then nothing", 33)}) {
    try {
      ForeignDatabase::from_bytes(bytes, "the upload");
      ADD_FAILURE() << "accepted";
    } catch (const core::Error& e) {
      EXPECT_EQ(e.code(), core::ErrorCode::bad_request) << e.what();
      EXPECT_TRUE(std::string(e.what()).starts_with("the upload ")) << e.what();
    }
  }
}

}  // namespace
}  // namespace hrisim::storage
