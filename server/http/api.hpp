#pragma once
// The REST API of hrisim: builds the router with every endpoint, bound to the services it needs.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "http/access.hpp"
#include "http/router.hpp"
#include "http/scenario_catalogue.hpp"
#include "http/session_limits.hpp"
#include "scenario/load.hpp"

namespace hrisim::storage {
class Store;
}
namespace hrisim::runs {
class Executor;
}

namespace hrisim::http {

struct ApiContext {
  storage::Store* store = nullptr;       ///< must outlive the router
  std::filesystem::path web_root;        ///< browser UI served at /
  std::filesystem::path scenarios_dir;   ///< bundled scenarios
  AccessPolicy access;                   ///< tokens, allowed origins and hosts
  live::SessionLimits sessions;                ///< how many live sessions, how long they may idle
  runs::Executor* executor = nullptr;    ///< runs the episodes of runs; must outlive the router
  scenario::ScenarioLimits scenario_limits;  ///< what one scenario may ask for
  std::size_t scenario_cache_bytes = kDefaultScenarioCacheBytes;  ///< compiled uploads kept in memory
  /// Where videos of episodes are written; a new folder of this router's own under the system's
  /// temporary folder when empty. Removed with the router.
  std::filesystem::path videos_dir;
};

/// Build and library versions, as served at /api/v1/version.
nlohmann::json version_info();

/// The router for `hrisim serve`: health, version, API description and the browser UI.
std::shared_ptr<const Router> make_api_router(const ApiContext& context);

}  // namespace hrisim::http
