// Private: small helpers to write MJCF text with a fixed number format, so generated models are
// byte-for-byte reproducible (models/gator.xml is compared against the generator).
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

#include "ovpc/core/types.h"

namespace ovpc::sim::xml {

/// Up to 9 significant digits, no trailing zeros, "-0" written as "0".
inline std::string Num(double value) {
  if (value == 0.0 || std::abs(value) < 1e-12) return "0";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.9g", value);
  return buffer;
}

inline std::string Vec(const Vec3& v) { return Num(v.x()) + " " + Num(v.y()) + " " + Num(v.z()); }

inline std::string Vec(double a, double b, double c) { return Num(a) + " " + Num(b) + " " + Num(c); }

/// MuJoCo quaternion order: w x y z.
inline std::string Quat(const Eigen::Quaterniond& q) {
  return Num(q.w()) + " " + Num(q.x()) + " " + Num(q.y()) + " " + Num(q.z());
}

inline std::string Rgba(double r, double g, double b, double a = 1.0) {
  return Num(r) + " " + Num(g) + " " + Num(b) + " " + Num(a);
}

}  // namespace ovpc::sim::xml
