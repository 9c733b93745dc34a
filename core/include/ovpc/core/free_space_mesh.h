// The watertight free-space mesh produced by GHPR (see ghpr.h) and its geometric checks.
#pragma once

#include <cstdint>
#include <vector>

#include "ovpc/core/types.h"

namespace ovpc {

/// A closed triangle mesh around the viewpoint. The volume it encloses is the conservative estimate
/// of free space; outside is unknown.
///
/// Orientation: each triangle (a, b, c) has its right-hand normal (b - a) x (c - a) pointing *into*
/// the enclosed free space (towards the viewpoint side). So ground faces point up, ceiling faces down.
///
/// Vertices are the visible points of the input cloud. When nothing was observed above or behind the
/// sensor the viewpoint itself is a vertex of the hull; it is then kept as the last vertex
/// (`viewpoint_vertex`), the faces that touch it close the mesh, and they are never traversable: they
/// stand for the boundary of what was seen, not for a surface.
struct FreeSpaceMesh {
  Points vertices;                      ///< visible points, then the viewpoint if it is on the hull
  std::vector<int> source_index;        ///< per vertex: index into the input cloud, -1 for the viewpoint
  std::vector<Triangle> triangles;      ///< indices into `vertices`
  std::vector<Vec3> face_normals;       ///< unit normals into free space, one per triangle
  std::vector<std::uint8_t> face_traversable;  ///< 1 if the face passes the traversability test
  int viewpoint_vertex = -1;            ///< index of the viewpoint in `vertices`, or -1
  /// The point the mesh was made from. The mesh is star-shaped around it, so every visible point
  /// sees it through free space: the free side of the surface at a vertex is the viewpoint's side.
  Vec3 viewpoint = Vec3::Zero();

  std::size_t num_visible() const {
    return vertices.size() - (viewpoint_vertex >= 0 ? 1 : 0);
  }
  bool TouchesViewpoint(std::size_t face) const {
    const Triangle& t = triangles[face];
    return viewpoint_vertex >= 0 &&
           (t[0] == viewpoint_vertex || t[1] == viewpoint_vertex || t[2] == viewpoint_vertex);
  }
};

/// Result of the topological checks on a mesh.
struct MeshTopology {
  std::size_t num_vertices = 0;
  std::size_t num_edges = 0;
  std::size_t num_faces = 0;
  bool every_edge_in_two_faces = false;  ///< closed, manifold edges
  bool consistently_oriented = false;    ///< every directed edge used exactly once
  bool no_degenerate_faces = false;      ///< no face repeats a vertex
  int euler_characteristic = 0;          ///< V - E + F

  /// Watertight as the project means it: closed, manifold edges, oriented, sphere topology (chi = 2).
  bool watertight() const {
    return every_edge_in_two_faces && consistently_oriented && no_degenerate_faces &&
           euler_characteristic == 2;
  }
};

/// Counts edges and checks that the mesh is closed, oriented and of sphere topology.
/// Only vertices referenced by a triangle are counted in V.
MeshTopology CheckTopology(const std::vector<Triangle>& triangles);

/// Volume enclosed by a closed mesh whose normals point inwards (as in FreeSpaceMesh), in m^3.
/// Positive for a correctly oriented mesh.
double EnclosedVolume(const Points& vertices, const std::vector<Triangle>& triangles);

}  // namespace ovpc
