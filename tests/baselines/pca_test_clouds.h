// Small analytic clouds for the normal-estimation tests.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

#include "ovpc/core/types.h"

namespace ovpc::baselines::testing {

/// Two unit vectors spanning the plane with unit normal `normal`.
inline void PlaneBasis(const Vec3& normal, Vec3* u, Vec3* v) {
  const Vec3 helper = std::abs(normal.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  *u = normal.cross(helper).normalized();
  *v = normal.cross(*u);
}

/// A square grid of step `spacing` and half side `half_size` on the plane through `centre` with
/// unit normal `normal`, each point moved along the normal by uniform noise in [-noise, noise]
/// (seeded).
inline Points PlanePatch(const Vec3& centre, const Vec3& normal, double half_size, double spacing,
                         double noise, std::uint64_t seed) {
  Vec3 u;
  Vec3 v;
  PlaneBasis(normal, &u, &v);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> offset(-1.0, 1.0);
  const int steps = static_cast<int>(std::floor(2.0 * half_size / spacing + 1e-9));
  Points points;
  for (int i = 0; i <= steps; ++i) {
    for (int j = 0; j <= steps; ++j) {
      const double du = -half_size + i * spacing;
      const double dv = -half_size + j * spacing;
      points.push_back(centre + du * u + dv * v + noise * offset(rng) * normal);
    }
  }
  return points;
}

}  // namespace ovpc::baselines::testing
