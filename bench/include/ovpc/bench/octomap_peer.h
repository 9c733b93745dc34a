// OctoMap as the benchmarks' comparison peer: the conversion to its cloud type (outside the timed
// region) and one timed insertion into a fresh tree.
#pragma once

#include <cstddef>

#include <octomap/octomap.h>

#include "ovpc/core/types.h"

namespace ovpc::bench {

octomap::Pointcloud ToOctomap(const Points& points);

struct OctomapRun {
  double ms = 0.0;          ///< wall clock of insertPointCloud alone
  std::size_t nodes = 0;    ///< nodes of the resulting tree
};

/// A fresh `octomap::OcTree(resolution_m)` (built outside the timed region), then
/// `insertPointCloud(cloud, origin)` timed with the steady clock, no max range. The tree is
/// destroyed after the clock stopped.
OctomapRun InsertIntoFreshOctree(const octomap::Pointcloud& cloud, double resolution_m,
                                 const Vec3& origin = Vec3::Zero());

}  // namespace ovpc::bench
