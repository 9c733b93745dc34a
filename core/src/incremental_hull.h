// Internal: an exact incremental 3D convex hull specialised for GHPR image sets.
//
// Points are inserted in a spatially coherent order (Morton order within biased random rounds).
// The hull always contains its first tetrahedron, so it is star-shaped around that tetrahedron's
// centroid: each new point is located by walking over the facets towards its direction from the
// centre, then either discarded (inside the facet's cone, below the facet: inside the hull for good)
// or inserted (visible facets removed, the horizon coned to the point). There are no conflict lists,
// so each point is looked at once.
//
// Every decision is an exact orientation sign: a floating-point evaluation with a proven error bound,
// and CGAL's exact `orientation` when the bound cannot decide. The hull of points in general position
// is unique, so the result equals CGAL's `convex_hull_3`. When a decisive orientation is zero (four
// coplanar points, duplicates) the function reports kDegenerate and the caller uses CGAL instead.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "ovpc/core/types.h"

namespace ovpc::internal {

enum class HullStatus { kOk, kDegenerate };

/// Working memory reused from one call to the next, so that a map update allocates nothing once the
/// buffers have grown to the cloud size.
struct HullWorkspace {
  struct Facet {
    std::array<int, 3> v;   // vertices, counter-clockwise seen from outside
    std::array<int, 3> nb;  // nb[i]: facet across edge (v[i], v[i+1])
    Vec3 normal;            // (v1 - v0) x (v2 - v0), outward, not normalised
    double error_scale;     // error bound of normal . (p - v0) is error_scale * |p - v0|_1
    std::uint32_t stamp;    // visit mark of the current insertion
    bool above;             // tested against the current point: strictly above its plane
    bool alive;
  };
  std::vector<Facet> facets;
  std::vector<int> free_facets;
  std::vector<int> order;
  std::vector<std::pair<std::uint64_t, int>> keyed;      // (sort key, point) for the insertion order
  std::vector<std::pair<std::uint64_t, int>> keyed_tmp;
  std::vector<int> visible;
  std::vector<int> stack;
  std::vector<std::array<int, 3>> horizon;  // (facet outside, edge start, edge end)
  std::vector<int> new_facet_from;          // per point: new facet whose horizon edge starts there
  std::vector<int> new_facet_to;            // per point: new facet whose horizon edge ends there
  std::uint32_t stamp = 0;
};

/// Exact convex hull of `points` (all finite). On kOk, `faces` holds the hull triangles as indices
/// into `points`, oriented counter-clockwise seen from outside, and `vertices` the hull vertices in
/// ascending order. On kDegenerate the outputs are unspecified.
HullStatus IncrementalHull(const Points& points, HullWorkspace* workspace, std::vector<int>* vertices,
                           std::vector<std::array<int, 3>>* faces);

}  // namespace ovpc::internal
