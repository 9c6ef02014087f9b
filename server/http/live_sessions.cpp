#include "http/live_sessions.hpp"

namespace hrisim::http {

Response locked(std::shared_ptr<Live> live, std::function<Response(Live&)> work) {
  if (std::unique_lock lock(live->mutex, std::try_to_lock); lock) return work(*live);
  return Response::later([live = std::move(live), work = std::move(work)] {
    std::lock_guard lock(live->mutex);
    return work(*live);
  });
}

}  // namespace hrisim::http
