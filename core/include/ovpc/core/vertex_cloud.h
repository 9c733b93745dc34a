// The planner's map: the visible points with normals and traversability, and a k-d tree over them.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "ovpc/core/free_space_mesh.h"

namespace ovpc {

/// Immutable vertex cloud (paper: "a point cloud is formed from the vertices of the mesh"). It is 3D,
/// not a 2.5D grid, so a roof and the ground under it coexist. Copies share the same data.
class TraversabilityCloud {
 public:
  struct Neighbor {
    int index = -1;
    double distance_m = 0.0;
  };

  TraversabilityCloud();
  /// @throws std::invalid_argument if the three vectors differ in size.
  TraversabilityCloud(Points points, std::vector<Vec3> normals, std::vector<std::uint8_t> traversable);

  std::size_t size() const;
  bool empty() const { return size() == 0; }
  const Points& points() const;
  const std::vector<Vec3>& normals() const;
  const std::vector<std::uint8_t>& traversable() const;

  /// Nearest point to `query`, or nothing if the cloud is empty.
  std::optional<Neighbor> Nearest(const Vec3& query) const;
  /// The up to `k` points nearest to `query`, nearest first, into `out` (cleared first); none if the
  /// cloud is empty or the query is not finite.
  void KNearest(const Vec3& query, std::size_t k, std::vector<Neighbor>* out) const;
  /// All points within `radius_m` of `query`, sorted by distance.
  std::vector<Neighbor> WithinRadius(const Vec3& query, double radius_m) const;
  /// Indices of all points inside the oriented box with centre pose `T_L_B` (box frame B in the
  /// cloud frame L) and the given half extents, in ascending index order.
  std::vector<int> InBox(const Eigen::Isometry3d& T_L_B, const Vec3& half_extents_m) const;

 private:
  struct Data;
  std::shared_ptr<const Data> data_;
};

/// Vertex normals and flags from a classified mesh: the normal of a visible point is the normalised
/// mean of the normals of its adjacent observed faces (faces touching the viewpoint are not
/// surfaces and are left out of the mean); it is traversable only if every adjacent face, including
/// those touching the viewpoint, is traversable. Point i of the cloud is mesh vertex i.
/// @pre ClassifyFaces was run on `mesh`.
TraversabilityCloud BuildTraversabilityCloud(const FreeSpaceMesh& mesh);

}  // namespace ovpc
