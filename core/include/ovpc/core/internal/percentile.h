// Shared by the project's libraries, not a stable API: the one percentile rule of every reported
// figure (benchmarks, the navigator's stage timings).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace ovpc::internal {

/// Percentile `p` in [0, 1] of an ascending, non-empty sample, interpolated linearly between the
/// closest ranks (R-7, numpy's default).
inline double Percentile(const std::vector<double>& sorted, double p) {
  const double h = p * static_cast<double>(sorted.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

}  // namespace ovpc::internal
