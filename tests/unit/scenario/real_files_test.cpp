// Every published file of ../shared/external that hrisim imports (pedsim_ros and libpedsim scenes,
// HuNavSim 1 and 2 agents files, IMHuS choreographies) runs 120 s with at least 90 % of its people
// walking their routes (issue 42, item 5). Read in place; a checkout without ../shared skips these,
// and tests/unit/sim/walking_test.cpp covers the narrow passage they needed with the project's own map.
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>
#include <ostream>

#include "episode/episode.hpp"
#include "scenario/import.hpp"
#include "sim/session.hpp"
#include "support/imports.hpp"

namespace hrisim::scenario {
namespace {

using testing::kShared;
using testing::load_imported;
using testing::read;

/// How long each file runs, s, and the share of its people who must walk their routes in that time.
constexpr double kRunTime = 120.0;
constexpr double kWalkingShare = 0.9;
/// People sent on their way after this are left out: their route may not fit in what is left of the run, s.
constexpr double kLatestStart = 60.0;
/// A goal counts as reached within its radius and this, m (the walker stops at the radius exactly).
constexpr double kReachedTolerance = 0.05;
/// Someone whose goal is farther than the run lets them walk (the airport's halls are 100–300 m
/// across) walks their route when, along their path, they came nearer to it by at least this share of
/// what their preferred speed covers in the time they walked to it.
constexpr double kProgressShare = 0.5;

struct RealFile {
  const char* name;  ///< under ../shared/external
  const char* map;   ///< a HuNavSim file's map, "" for the others
};

/// GoogleTest prints a parameter by this, instead of its bytes, in test listings and failures.
void PrintTo(const RealFile& file, std::ostream* out) { *out << file.name; }

/// What a run shows of the people sent somewhere: who walked their routes.
struct Routes {
  std::vector<std::string> walking, not_walking;
};

/// People who walk their routes, precisely: those sent to a goal (by their routine, a queue, an
/// attraction, a source's route) within the first kLatestStart seconds of a kRunTime run (seed 1)
/// count; they walk their routes when they reached at least one goal they were sent to (they were
/// within its radius when they stopped walking to it or were sent on), or, still on their way to a
/// goal at the end, came nearer to it along their path by kProgressShare of what their preferred
/// speed covers in that time. People never sent anywhere (who stand by design, or follow a group's
/// leader) have no route of their own and count in neither.
Routes routes_walked(const std::shared_ptr<const Model>& model) {
  episode::Settings settings;
  settings.record = false;
  settings.time_limit = kRunTime;
  episode::Episode run(model, 1, settings);
  const auto& agents = run.session().state().agents;
  struct Leg {
    bool under_way = false;
    Vec2 goal = Vec2::Zero();
    double radius = 0.0;
    double started = 0.0;    ///< s
    double remaining = 0.0;  ///< the walk left when it started, m
  };
  std::vector<Leg> legs(agents.size());
  std::vector<bool> sent(agents.size(), false), reached(agents.size(), false);
  double time = 0.0;
  while (!run.over()) {
    run.tick();
    time = static_cast<double>(run.session().state().tick) * model->dt;
    for (std::size_t a = 0; a < agents.size(); ++a) {
      if (model->agents[a].kind != AgentKind::human) continue;
      const sim::Navigation& now = agents[a].navigation;
      Leg& leg = legs[a];
      if (leg.under_way && (!now.under_way || now.goal != leg.goal)) {
        reached[a] = reached[a] || (agents[a].position - leg.goal).norm() <= leg.radius + kReachedTolerance;
        leg.under_way = false;
      }
      if (now.under_way && !leg.under_way) {
        leg = {true, now.goal, now.goal_radius, time, now.nearest_to_goal};
        sent[a] = sent[a] || time <= kLatestStart;
      }
    }
  }
  Routes routes;
  for (std::size_t a = 0; a < agents.size(); ++a) {
    if (!sent[a]) continue;
    const Leg& leg = legs[a];
    const double covered = leg.remaining - agents[a].navigation.nearest_to_goal;
    const bool on_their_way = leg.under_way && covered >= kProgressShare * agents[a].preferred_speed * (time - leg.started);
    (reached[a] || on_their_way ? routes.walking : routes.not_walking).push_back(model->agents[a].id);
  }
  return routes;
}

std::shared_ptr<const Model> import_real_file(const RealFile& file) {
  const std::filesystem::path path = kShared / "external" / file.name;
  ImportOptions options{"", std::nullopt, {path.parent_path(), std::filesystem::path(HRISIM_SOURCE_DIR) / "scenarios"}, path.filename().string(), {}, ""};
  options.limits.confine_files = false;
  if (*file.map) options.map = kShared / "external" / file.map;
  const std::string text = read(path);
  const ImportResult imported = path.extension() == ".yaml"              ? import_hunav(text, options)
                                : detect_xml_format(text) == "pedsim" ? import_pedsim(text, options)
                                                                       : import_imhus(text, options);
  LoadOptions load;
  load.map_search_path = options.map_search_path;
  load.limits.confine_files = false;
  return load_imported(imported, load);
}

class RealFiles : public ::testing::TestWithParam<RealFile> {};

TEST_P(RealFiles, NinetyPercentOfThePeopleWalkTheirRoutesIn120Seconds) {
  const RealFile file = GetParam();
  if (!std::filesystem::exists(kShared / "external" / file.name)) {
    GTEST_SKIP() << testing::no_reference_file(file.name, "tests/unit/sim/walking_test.cpp (Walking.PeoplePlanThroughADoorNarrowerThanTheirDiscButWiderThanTheirBody)");
  }
  const auto model = import_real_file(file);
  ASSERT_TRUE(model);
  const Routes routes = routes_walked(model);
  const std::size_t people = routes.walking.size() + routes.not_walking.size();
  std::string idle;
  for (const std::string& id : routes.not_walking) idle += " " + id;
  std::printf("%s: %zu of %zu people walk their routes\n", file.name, routes.walking.size(), people);
  ASSERT_GT(people, 0u) << "someone is sent somewhere";
  EXPECT_GE(static_cast<double>(routes.walking.size()), kWalkingShare * static_cast<double>(people))
      << routes.walking.size() << " of " << people << " walk their routes; reached no goal:" << idle;
}

INSTANTIATE_TEST_SUITE_P(
    External, RealFiles,
    ::testing::Values(RealFile{"pedsim/corridor.xml", ""}, RealFile{"pedsim/libpedsim_scene.xml", ""}, RealFile{"pedsim/pedsim_ros_airport.xml", ""},
                      RealFile{"pedsim/pedsim_ros_airport_activities.xml", ""}, RealFile{"pedsim/pedsim_ros_scene1.xml", ""},
                      RealFile{"pedsim/pedsim_ros_social_contexts.xml", ""}, RealFile{"pedsim/suminkxng_khu5th.xml", ""},
                      RealFile{"pedsim/templerail_autolab_25.xml", ""}, RealFile{"pedsim/templerail_cumberland.xml", ""},
                      RealFile{"pedsim/templerail_eng_hall.xml", ""}, RealFile{"pedsim/templerail_nav_test.xml", ""},
                      RealFile{"hunav/agents.yaml", "hunav/maps/map_cafe2.yaml"}, RealFile{"hunav2/office_agents.yaml", "hunav2/office.yaml"},
                      RealFile{"imhus/elevator_goals.xml", ""}, RealFile{"imhus/videos_goals.xml", ""}),
    [](const ::testing::TestParamInfo<RealFile>& info) {
      std::string name = info.param.name;
      for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
      return name;
    });

}  // namespace
}  // namespace hrisim::scenario
