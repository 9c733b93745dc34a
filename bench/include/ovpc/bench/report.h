// Timing and report helpers shared by the benchmark programs: the clock, the machine and build
// description printed with every result, and CSV/JSON quoting.
#pragma once

#include <chrono>
#include <string>

namespace ovpc::bench {

using Clock = std::chrono::steady_clock;

inline double MsSince(Clock::time_point start, Clock::time_point stop) {
  return std::chrono::duration<double, std::milli>(stop - start).count();
}

/// The CPU model from /proc/cpuinfo, or "unknown".
std::string MachineName();

/// The 1-minute load average from /proc/loadavg, or a negative value when unknown: timings on a
/// machine shared with other work are reported with it.
double LoadAverage1Min();

/// The CMake build type and whether the benchmark code was optimised and built with NDEBUG (timings
/// of an unoptimised build are flagged as not meaningful).
std::string BuildType();

/// `text` as one CSV field: quoted only if it contains a comma, a quote or a newline.
std::string CsvField(const std::string& text);

/// `text` escaped for a JSON string (without the surrounding quotes).
std::string JsonEscape(const std::string& text);

}  // namespace ovpc::bench
