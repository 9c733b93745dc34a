// Shared by the project's libraries, not a stable API: the clocks that stage timings are read
// from. Timings are reported, never used to decide anything (the loop runs on simulated time).
#pragma once

#include <time.h>

#include <chrono>

namespace ovpc::internal {

using Clock = std::chrono::steady_clock;

/// Milliseconds of wall time since `start`.
inline double MsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// CPU time of the calling thread in milliseconds. Unlike the wall clock it does not count the time
/// the thread waits for a core, so it holds on a loaded machine (several runs side by side).
inline double ThreadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

}  // namespace ovpc::internal
