// The planner's map: the visible points with normals and traversability, and a k-d tree over them.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "ovpc/core/config_fields.h"
#include "ovpc/core/free_space_mesh.h"

namespace ovpc {

/// How each visible point gets its normal (BuildTraversabilityCloud).
struct VertexNormals {
  enum class Rule : std::uint8_t {
    /// The normalised mean of the normals of the point's observed faces (the paper's rule). Range
    /// noise tilts small faces, and with them these normals: 6.1 deg mean error on the paper's
    /// normals protocol (docs/PAPER_REPRODUCTION.md).
    kMeanOfFaces,
    /// The normal of the least-squares plane through the point and its nearest visible points
    /// (at most max_patch_points, itself included, within radius_m), turned into free space: to
    /// the mean-of-faces normal's side where the two agree within 60 deg either way, else to the
    /// viewpoint's side (the mesh is star-shaped around it). A patch of fewer than four points
    /// (three always span a plane), or one that is no plane (its two smallest spreads within a
    /// factor of 4: a line or a blob), keeps the mean-of-faces normal. A point without an observed
    /// face gets none.
    kPlaneFit,
  };
  struct Config {
    Rule rule = Rule::kPlaneFit;
    double radius_m = 0.5;      ///< plane_fit: the patch's points lie within this of the point
    int max_patch_points = 32;  ///< plane_fit: at most this many nearest points, itself included (4-256)
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Choice(OVPC_FIELD(c, rule),
               Choices<Rule>{{"mean_of_faces", Rule::kMeanOfFaces}, {"plane_fit", Rule::kPlaneFit}},
               "mean_of_faces: the paper's; plane_fit: fitted over the neighbours, a third of the error");
      v.Field(OVPC_FIELD(c, radius_m), "m", "plane_fit: the patch's radius");
      v.Field(OVPC_FIELD(c, max_patch_points), "points", "plane_fit: the patch's nearest points at most");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };
};

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
  /// Whether point i is a foot: non-traversable, and each of its non-traversable faces rises from it
  /// close by, higher than a step (another vertex of the face lies more than 0.25 m above it and
  /// within 2 m of it in the plane, none more than 5 cm below it): the foot of a wall or a post. A
  /// lip, whose steep faces fall away, is not, nor the foot of a steep ramp (its faces rise a few
  /// centimetres to the ramp's next points), nor the rim of what was seen (a point with a face to
  /// the viewpoint that is not traversable), nor ground far past an obstacle, whose face reaches
  /// metres up to the obstacle's top. Always false for a cloud made from flags alone (the
  /// three-vector constructor) and for i out of range.
  bool IsFoot(std::size_t i) const;

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
  explicit TraversabilityCloud(std::shared_ptr<const Data> data) : data_(std::move(data)) {}
  friend TraversabilityCloud BuildTraversabilityCloud(const FreeSpaceMesh& mesh, const VertexNormals::Config& normals);
  std::shared_ptr<const Data> data_;
};

/// Vertex normals and flags from a classified mesh. A visible point's normal follows
/// `normals.rule`: the normalised mean of the normals of its adjacent observed faces (faces touching
/// the viewpoint are not surfaces and are left out of the mean), or the plane fitted over its
/// neighbours in the cloud (found with the cloud's own k-d tree) turned into free space. A
/// point without an observed face has no normal (zero) under either rule. It is traversable only if
/// every adjacent face, including those touching the viewpoint, is traversable (the flags do not
/// depend on the rule). Point i of the cloud is mesh vertex i.
/// @pre ClassifyFaces was run on `mesh`.
/// @throws std::invalid_argument if the mesh was not classified or `normals` is invalid.
TraversabilityCloud BuildTraversabilityCloud(const FreeSpaceMesh& mesh, const VertexNormals::Config& normals = {});

}  // namespace ovpc
