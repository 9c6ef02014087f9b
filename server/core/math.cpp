#include "core/math.hpp"

#include <sstream>

namespace hrisim::core {

std::string point_text(const Vec2& p) {
  std::ostringstream out;
  out << p.x() << ", " << p.y();
  return out.str();
}

}  // namespace hrisim::core
