#pragma once
// Runs over REST: submit a batch of headless episodes (scenario × seeds × controller, with gates), follow
// its progress, cancel it, read its report, episodes, trajectories and JUnit XML; and the metric
// definitions. The episodes run on the executor's threads, never on an I/O thread.
#include <memory>

#include "http/router.hpp"
#include "http/scenario_catalogue.hpp"

namespace hrisim::runs {
class Executor;
}

namespace hrisim::http {

void add_run_routes(Router& router, std::shared_ptr<ScenarioCatalogue> catalogue, storage::Store* store, runs::Executor* executor);

}  // namespace hrisim::http
