// The OctoMap backend's map: the buffered cloud inserted into an octomap::OcTree as OctoMap does it
// (one scan, rays from the viewpoint, its default sensor model), then read into columns. OctoMap
// stays out of this header.
#pragma once

#include <cstddef>
#include <memory>

#include "ovpc/backends/column_map.h"
#include "ovpc/core/types.h"

namespace ovpc::backends {

/// A fresh OcTree per Insert. In the columns: every occupied voxel is a sample (its centre); the top
/// of each vertical run of occupied voxels is a ground candidate when the voxel right above it is
/// known free (a ray passed through it). A run whose next voxel up is unknown or out of the tree is
/// no ground: a roof seen from below, a wall's top the sensor did not see over.
class OctoMapColumns {
 public:
  /// @throws std::invalid_argument unless 0.01 <= resolution_m <= 10.
  explicit OctoMapColumns(double resolution_m);
  ~OctoMapColumns();
  OctoMapColumns(const OctoMapColumns&) = delete;
  OctoMapColumns& operator=(const OctoMapColumns&) = delete;

  /// Replaces the tree by one built from `points` seen from `origin`: OcTree::insertPointCloud with
  /// no range limit. Non-finite points are skipped.
  void Insert(const Points& points, const Vec3& origin);
  /// The tree read into columns (empty before the first Insert).
  ColumnGrid Columns() const;

  double resolution_m() const { return resolution_m_; }
  /// Nodes of the latest tree (OcTree::size), for logs.
  std::size_t tree_nodes() const;
  /// Occupancy of the voxel containing p in the latest tree: 1 occupied, 0 free, -1 unknown.
  int Occupancy(const Vec3& p) const;

 private:
  struct Tree;
  double resolution_m_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace ovpc::backends
