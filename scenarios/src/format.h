// Number formatting shared by the scorecard, the referee's criteria and the recorder's file names.
#pragma once

#include <iomanip>
#include <sstream>
#include <string>

namespace ovpc::scenarios::internal {

/// `v` with `digits` digits after the point.
inline std::string Fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

}  // namespace ovpc::scenarios::internal
