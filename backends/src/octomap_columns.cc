#include "ovpc/backends/octomap_columns.h"

#include <octomap/OcTree.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace ovpc::backends {

struct OctoMapColumns::Tree {
  explicit Tree(double resolution_m) : tree(resolution_m) {}
  octomap::OcTree tree;
};

OctoMapColumns::OctoMapColumns(double resolution_m) : resolution_m_(resolution_m) {
  if (!(resolution_m >= 0.01 && resolution_m <= 10.0)) {
    throw std::invalid_argument("OctoMapColumns: resolution_m must be in [0.01, 10], got " + std::to_string(resolution_m));
  }
}

OctoMapColumns::~OctoMapColumns() = default;

void OctoMapColumns::Insert(const Points& points, const Vec3& origin) {
  tree_ = std::make_unique<Tree>(resolution_m_);
  octomap::Pointcloud cloud;
  cloud.reserve(points.size());
  for (const Vec3& p : points) {
    if (p.allFinite()) cloud.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  }
  const octomap::point3d sensor(static_cast<float>(origin.x()), static_cast<float>(origin.y()), static_cast<float>(origin.z()));
  tree_->tree.insertPointCloud(cloud, sensor);
}

std::size_t OctoMapColumns::tree_nodes() const { return tree_ ? tree_->tree.size() : 0; }

int OctoMapColumns::Occupancy(const Vec3& p) const {
  if (!tree_) return -1;
  const octomap::OcTreeNode* node = tree_->tree.search(p.x(), p.y(), p.z());
  if (node == nullptr) return -1;
  return tree_->tree.isNodeOccupied(node) ? 1 : 0;
}

ColumnGrid OctoMapColumns::Columns() const {
  ColumnGrid grid;
  grid.resolution_m = resolution_m_;
  grid.Reset(resolution_m_, 0.0, 0.0, 0, 0);
  if (!tree_) return grid;
  const octomap::OcTree& tree = tree_->tree;
  // Every occupied voxel at the finest depth (a pruned occupied node stands for all its voxels).
  using Key = std::array<std::uint16_t, 3>;  // y, x, z: sorted into the grid's row-major order
  std::vector<Key> keys;
  const unsigned depth = tree.getTreeDepth();
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const octomap::OcTreeKey base = it.getIndexKey();
    const unsigned span = 1u << (depth - it.getDepth());
    for (unsigned dy = 0; dy < span; ++dy) {
      for (unsigned dx = 0; dx < span; ++dx) {
        for (unsigned dz = 0; dz < span; ++dz) {
          keys.push_back({static_cast<std::uint16_t>(base[1] + dy), static_cast<std::uint16_t>(base[0] + dx),
                          static_cast<std::uint16_t>(base[2] + dz)});
        }
      }
    }
  }
  if (keys.empty()) return grid;
  std::sort(keys.begin(), keys.end());
  std::uint16_t min_x = keys.front()[1], max_x = min_x, min_y = keys.front()[0], max_y = keys.back()[0];
  for (const Key& k : keys) min_x = std::min(min_x, k[1]), max_x = std::max(max_x, k[1]);
  const double res = resolution_m_;
  grid.Reset(res, tree.keyToCoord(min_x) - 0.5 * res, tree.keyToCoord(min_y) - 0.5 * res, max_x - min_x + 1, max_y - min_y + 1);
  grid.sample_z.reserve(keys.size());
  grid.sample_ground.reserve(keys.size());
  std::size_t i = 0;
  for (std::size_t c = 0; c < grid.num_columns(); ++c) {
    const auto ky = static_cast<std::uint16_t>(min_y + c / grid.nx), kx = static_cast<std::uint16_t>(min_x + c % grid.nx);
    // This column's voxels, bottom up, in runs of consecutive voxels.
    while (i < keys.size() && keys[i][0] == ky && keys[i][1] == kx) {
      std::size_t run_end = i + 1;
      while (run_end < keys.size() && keys[run_end][0] == ky && keys[run_end][1] == kx &&
             keys[run_end][2] == keys[run_end - 1][2] + 1) {
        ++run_end;
      }
      const std::uint16_t top = keys[run_end - 1][2];
      std::int32_t ground = -1;
      if (top < 0xFFFF) {
        const octomap::OcTreeNode* above = tree.search(octomap::OcTreeKey(kx, ky, static_cast<std::uint16_t>(top + 1)));
        if (above != nullptr && !tree.isNodeOccupied(above)) {
          ground = static_cast<std::int32_t>(grid.ground_z.size());
          grid.ground_z.push_back(static_cast<float>(tree.keyToCoord(top)));
        }
      }
      for (std::size_t k = i; k < run_end; ++k) {
        grid.sample_z.push_back(static_cast<float>(tree.keyToCoord(keys[k][2])));
        grid.sample_ground.push_back(ground);
      }
      i = run_end;
    }
    grid.ground_begin[c + 1] = static_cast<std::uint32_t>(grid.ground_z.size());
    grid.sample_begin[c + 1] = static_cast<std::uint32_t>(grid.sample_z.size());
  }
  return grid;
}

}  // namespace ovpc::backends
