#pragma once
// The scenarios routes: list (bundled and uploaded, with summaries), get (the native JSON), upload
// (native JSON, IMHuS XML or Pedsim XML; stored with its source and hash) and validate (all errors,
// located, nothing stored).
#include <filesystem>

#include "http/router.hpp"

namespace hrisim::storage {
class Store;
}

namespace hrisim::http {

/// Deepest nesting of arrays and objects accepted in a JSON body (a scenario needs about 10).
inline constexpr int kMaxJsonDepth = 64;
/// Largest `limit` of a scenarios page; the default page size.
inline constexpr int kMaxPageSize = 200;
inline constexpr int kDefaultPageSize = 50;

void add_scenario_routes(Router& router, storage::Store* store, const std::filesystem::path& scenarios_dir);

}  // namespace hrisim::http
