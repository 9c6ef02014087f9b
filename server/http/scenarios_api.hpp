#pragma once
// The scenarios routes: list (bundled and uploaded, with summaries), get (the native JSON), a
// thumbnail (the map from above at the start), upload (native JSON, IMHuS XML or Pedsim XML; stored
// with its source and hash) and validate (all errors, located, nothing stored).
#include <memory>

#include "http/router.hpp"
#include "http/scenario_catalogue.hpp"

namespace hrisim::http {

/// Largest `limit` of a scenarios page; the default page size.
inline constexpr int kMaxPageSize = 200;
inline constexpr int kDefaultPageSize = 50;
/// Thumbnail size by default and at most, pixels.
inline constexpr int kThumbnailWidth = 320;
inline constexpr int kThumbnailHeight = 240;
inline constexpr int kMaxThumbnailSize = 1024;

void add_scenario_routes(Router& router, std::shared_ptr<ScenarioCatalogue> catalogue);

}  // namespace hrisim::http
