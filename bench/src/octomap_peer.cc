#include "ovpc/bench/octomap_peer.h"

#include <memory>

#include "ovpc/bench/report.h"

namespace ovpc::bench {

octomap::Pointcloud ToOctomap(const Points& points) {
  octomap::Pointcloud cloud;
  cloud.reserve(points.size());
  for (const Vec3& p : points) {
    cloud.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                    static_cast<float>(p.z()));
  }
  return cloud;
}

OctomapRun InsertIntoFreshOctree(const octomap::Pointcloud& cloud, double resolution_m,
                                 const Vec3& origin) {
  auto tree = std::make_unique<octomap::OcTree>(resolution_m);
  const octomap::point3d sensor(static_cast<float>(origin.x()), static_cast<float>(origin.y()),
                                static_cast<float>(origin.z()));
  const Clock::time_point start = Clock::now();
  tree->insertPointCloud(cloud, sensor);
  const Clock::time_point stop = Clock::now();
  return {MsSince(start, stop), tree->size()};
}

}  // namespace ovpc::bench
