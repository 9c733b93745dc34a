// Internal helpers shared by the core's sources (not installed, not part of the API).
#pragma once

#include <chrono>
#include <cstdint>

namespace ovpc::internal {

/// splitmix64: a fixed, platform-independent mixing function, for deterministic pseudo-random
/// choices (subsampling, insertion order, hashing voxel keys).
inline std::uint64_t Mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

using Clock = std::chrono::steady_clock;

/// Wall-clock milliseconds since `start`, for reported timings only.
inline double MsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace ovpc::internal
