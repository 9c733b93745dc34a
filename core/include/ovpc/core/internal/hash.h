// Shared by the project's libraries, not a stable API: the one 64-bit mix behind every hash and
// deterministic random choice (buffer subsampling, voxel and cell keys, the simulator's noise,
// family draws, scenario layouts).
#pragma once

#include <cstdint>

namespace ovpc::internal {

/// splitmix64's increment (the golden gamma, Steele, Lea and Flood 2014).
inline constexpr std::uint64_t kGoldenGamma = 0x9e3779b97f4a7c15ULL;

/// splitmix64's output function: a bijective 64-bit mix.
inline std::uint64_t MixBits(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// splitmix64: the value a stream whose state is `x` gives next, MixBits(x + kGoldenGamma).
inline std::uint64_t Mix(std::uint64_t x) { return MixBits(x + kGoldenGamma); }

/// The hash of an integer cell (voxel) key, for the open-addressing cell tables.
inline std::uint64_t HashCellKey(std::int64_t k0, std::int64_t k1, std::int64_t k2) {
  return Mix(static_cast<std::uint64_t>(k0) * kGoldenGamma ^ static_cast<std::uint64_t>(k1) * 0xc2b2ae3d27d4eb4fULL ^
             static_cast<std::uint64_t>(k2) * 0x165667b19e3779f9ULL);
}

/// The top 53 bits of `x` as a double in [0, 1).
inline double ToUnitInterval(std::uint64_t x) { return static_cast<double>(x >> 11) * 0x1.0p-53; }

}  // namespace ovpc::internal
