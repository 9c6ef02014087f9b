#include "core/math.hpp"

#include <sstream>

namespace hrisim::core {

std::string point_text(const Vec2& p) { return number_text(p.x()) + ", " + number_text(p.y()); }

std::string number_text(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

}  // namespace hrisim::core
