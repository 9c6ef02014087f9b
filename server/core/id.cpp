#include "core/id.hpp"

#include <nlohmann/json.hpp>

namespace hrisim::core {

void throw_unknown_id(std::uint32_t index, std::uint32_t generation) {
  throw Error(ErrorCode::not_found, "stale or unknown entity id (slot " + std::to_string(index) + ", generation " + std::to_string(generation) + ")",
              {{"index", index}, {"generation", generation}});
}

}  // namespace hrisim::core
