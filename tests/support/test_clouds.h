// Analytic clouds and mesh checks shared by the tests.
#pragma once

#include <cmath>
#include <vector>

#include "ovpc/core/types.h"

namespace ovpc::testing {

/// Points on the six faces of an axis-aligned box [-half, half], on a grid of the given spacing.
/// Edge points appear once.
inline Points BoxRoom(const Vec3& half, double spacing) {
  Points pts;
  const auto steps = [spacing](double h) { return static_cast<int>(std::lround(2.0 * h / spacing)); };
  const int nx = steps(half.x()), ny = steps(half.y()), nz = steps(half.z());
  for (int i = 0; i <= nx; ++i) {
    for (int j = 0; j <= ny; ++j) {
      for (int k = 0; k <= nz; ++k) {
        if (i != 0 && i != nx && j != 0 && j != ny && k != 0 && k != nz) continue;  // interior
        pts.emplace_back(-half.x() + 2.0 * half.x() * i / nx, -half.y() + 2.0 * half.y() * j / ny,
                         -half.z() + 2.0 * half.z() * k / nz);
      }
    }
  }
  return pts;
}

/// A planar grid z = height over [x0, x1] x [y0, y1].
inline Points Grid(double x0, double x1, double y0, double y1, double height, double spacing) {
  Points pts;
  for (double x = x0; x <= x1 + 1e-9; x += spacing) {
    for (double y = y0; y <= y1 + 1e-9; y += spacing) pts.emplace_back(x, y, height);
  }
  return pts;
}

}  // namespace ovpc::testing
