// Internal: the clocks the navigator's stage timings are read from.
#pragma once

#include <time.h>

#include <chrono>

namespace ovpc::navigation::internal {

using Clock = std::chrono::steady_clock;

/// Milliseconds of wall time since `t`.
inline double MsSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

/// CPU time of the calling thread in milliseconds. Unlike the wall clock it does not count the time
/// the thread waits for a core, so it holds on a loaded machine (several runs side by side).
inline double ThreadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

}  // namespace ovpc::navigation::internal
