// Number formatting shared by the scorecard, the referee's criteria, the recorder's file names and the
// YAML the scenarios write (configurations, drawn family members).
#pragma once

#include <cmath>
#include <cstdlib>
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

/// `text` as a message quotes it: whole when short, else its first 60 characters and "...", so that
/// a message stays one short line whatever a file holds.
inline std::string Abbreviated(const std::string& text) {
  constexpr std::size_t kShown = 60;
  return text.size() <= kShown + 20 ? text : text.substr(0, kShown) + "...";
}

/// The shortest decimal that reads back as the same double; .inf / -.inf / .nan as YAML spells them.
inline std::string FormatNumber(double v) {
  if (std::isnan(v)) return ".nan";
  if (std::isinf(v)) return v > 0 ? ".inf" : "-.inf";
  if (v == std::floor(v) && std::abs(v) < 1e15) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(0) << v;
    return s.str();
  }
  for (int digits = 1; digits <= 17; ++digits) {
    std::ostringstream s;
    s << std::setprecision(digits) << v;
    // strtod, not stod: a subnormal value reads back with ERANGE, which stod throws on.
    if (std::strtod(s.str().c_str(), nullptr) == v) return s.str();
  }
  return std::to_string(v);
}

}  // namespace ovpc::scenarios::internal
