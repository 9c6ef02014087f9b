#include "http/session_work.hpp"

namespace hrisim::http {

Response locked(std::shared_ptr<LiveSession> live, std::function<Response(LiveSession&)> work) {
  if (std::unique_lock lock(live->mutex, std::try_to_lock); lock) return work(*live);
  return Response::later([live = std::move(live), work = std::move(work)] {
    std::lock_guard lock(live->mutex);
    return work(*live);
  });
}

Response simulation_later(std::shared_ptr<void> place, std::function<Response()> work) {
  // Shared by every copy of the job, so that giving it back in the one that runs gives it back.
  auto held = std::make_shared<std::shared_ptr<void>>(std::move(place));
  return Response::later([held, work = std::move(work)] {
    struct GiveBack {
      std::shared_ptr<void>& place;
      ~GiveBack() { place.reset(); }
    } give_back{*held};
    return work();
  });
}

}  // namespace hrisim::http
