// The benchmarks' input clouds: buffered clouds of the generated outdoor scene
// (ovpc::synth::MakeOutdoorCloud), the stand-in for clouds taken from scenario runs until the
// closed loop exists.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ovpc/core/types.h"

namespace ovpc::bench {

struct BenchCloud {
  Points points;                ///< viewpoint at the origin, z up
  std::size_t target_size = 0;  ///< the buffer's subsampling target (points.size() may be smaller)
  std::uint64_t seed = 0;       ///< scene and noise seed
};

/// `count` clouds; cloud i is MakeOutdoorCloud(sizes[i % sizes.size()], first_seed + i), so every
/// cloud has its own scene and the sizes cycle through the list.
/// @throws std::invalid_argument if `sizes` is empty or a size is below 4.
std::vector<BenchCloud> MakeBenchClouds(const std::vector<std::size_t>& sizes,
                                        std::uint64_t first_seed, int count);

}  // namespace ovpc::bench
