#include "ovpc/bench/outdoor_clouds.h"

#include <stdexcept>

#include "ovpc/synth/synthetic_scene.h"

namespace ovpc::bench {

std::vector<BenchCloud> MakeBenchClouds(const std::vector<std::size_t>& sizes,
                                        std::uint64_t first_seed, int count) {
  if (sizes.empty()) throw std::invalid_argument("MakeBenchClouds: no sizes");
  for (const std::size_t size : sizes) {
    if (size < 4) throw std::invalid_argument("MakeBenchClouds: a size is below 4 points");
  }
  std::vector<BenchCloud> clouds;
  clouds.reserve(count > 0 ? static_cast<std::size_t>(count) : 0);
  for (int i = 0; i < count; ++i) {
    BenchCloud cloud;
    cloud.target_size = sizes[static_cast<std::size_t>(i) % sizes.size()];
    cloud.seed = first_seed + static_cast<std::uint64_t>(i);
    cloud.points = synth::MakeOutdoorCloud(cloud.target_size, cloud.seed);
    clouds.push_back(std::move(cloud));
  }
  return clouds;
}

}  // namespace ovpc::bench
