// The cache of compiled uploads counts what an upload expands to (issue 40, finding 7: it counted
// source bytes, so its limit did not bound a YAML file whose aliases expand into thousands of goals).
#include "http/scenario_catalogue.hpp"

#include <gtest/gtest.h>

#include "support/hunav_yaml.hpp"
#include "storage/store.hpp"
#include "support/temp_dir.hpp"

namespace hrisim::http {
namespace {

TEST(ScenarioCatalogue, TheCacheSizesAnUploadByWhatItsSourceExpandsTo) {
  testing::TempDir dir;
  storage::Store store(dir / "hrisim.db");
  ScenarioCatalogue catalogue(&store, dir / "no-bundled-scenarios");
  const std::string yaml = testing::aliased_goals(10, 5000);
  scenario::CompiledSource compiled;
  const auto added = catalogue.add({yaml, scenario::SourceFormat::hunav_yaml, {}}, "", compiled);
  ASSERT_FALSE(added.id.empty()) << (compiled.errors.empty() ? "" : compiled.errors[0].message);
  // 15 KB of YAML; 50,000 goals to walk, each a few values of the native document.
  EXPECT_LT(yaml.size(), 16u * 1024u);
  EXPECT_GT(catalogue.cached_bytes(), std::size_t{50'000} * 256) << "counted by the source's bytes, the entry was 0.2 MB";
}

TEST(ScenarioCatalogue, AFileInsideAnotherFilesPathIsFound) {
  EXPECT_FALSE(nested_upload_file({{"d", ""}, {"d-e", ""}, {"d.f/g", ""}}));
  const auto nested = nested_upload_file({{"maps/lab.yaml", ""}, {"maps", ""}});
  ASSERT_TRUE(nested);
  EXPECT_EQ(nested->file, "maps");
  EXPECT_EQ(nested->inside, "maps/lab.yaml");
  EXPECT_EQ(nested_upload_file({{"a/b/c", ""}, {"a/b", ""}})->file, "a/b");
}

}  // namespace
}  // namespace hrisim::http
