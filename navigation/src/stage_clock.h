// Internal: the wall clock the navigator's stage timings are read from.
#pragma once

#include <chrono>

namespace ovpc::navigation::internal {

using Clock = std::chrono::steady_clock;

/// Milliseconds of wall time since `t`.
inline double MsSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

}  // namespace ovpc::navigation::internal
