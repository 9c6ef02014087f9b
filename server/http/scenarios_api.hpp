#pragma once
// The scenarios routes: list (bundled and uploaded, with summaries), get (the native JSON), upload
// (native JSON, IMHuS XML or Pedsim XML; stored with its source and hash) and validate (all errors,
// located, nothing stored).
#include <memory>

#include "http/router.hpp"
#include "http/scenario_catalogue.hpp"

namespace hrisim::http {

/// Largest `limit` of a scenarios page; the default page size.
inline constexpr int kMaxPageSize = 200;
inline constexpr int kDefaultPageSize = 50;

void add_scenario_routes(Router& router, std::shared_ptr<ScenarioCatalogue> catalogue);

}  // namespace hrisim::http
