// General hidden point removal (GHPR, Katz & Tal 2015) and the free-space mesh from the hull.
#pragma once

#include <string>

#include "ovpc/core/free_space_mesh.h"
#include "ovpc/core/types.h"
#include "ovpc/core/config_fields.h"

namespace ovpc {

enum class GhprKernel {
  kExponential,  ///< f(d) = d^gamma, gamma < 0 (paper: -0.03)
  kLinear,       ///< f(d) = gamma - d, gamma > max d (gamma = 2R is spherical flipping)
};

/// The GHPR operator (ComputeGhpr).
struct Ghpr {
  struct Config {
    GhprKernel kernel = GhprKernel::kExponential;
    double gamma = -0.03;
    /// Compute every hull with CGAL's quickhull instead of the project's incremental hull. Both are
    /// exact and give the same mesh; CGAL's is slower and is the reference in tests and benchmarks.
    /// The incremental hull hands degenerate clouds (coplanar or duplicate points) to CGAL anyway.
    bool reference_hull = false;
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Choice(OVPC_FIELD(c, kernel), Choices<GhprKernel>{{"exponential", GhprKernel::kExponential}, {"linear", GhprKernel::kLinear}},
               "paper");
      v.Field(OVPC_FIELD(c, gamma), "", "paper (exponential kernel; linear: m)");
      v.Field(OVPC_FIELD(c, reference_hull), "", "CGAL's quickhull instead of the incremental hull (same mesh)");
    }
    /// @throws std::invalid_argument if gamma is not finite or out of range for the kernel: in
    /// [-1, 0) for the exponential one, in (0, 1e7] m for the linear one.
    void Validate() const;
  };
};

/// The farthest a point may be from the viewpoint, per coordinate, m. No sensor sees this far; beyond
/// it the squared distances and the cross products of the mesh stages could overflow (a point at
/// 1e299 m made d = inf and an all-zero image). OvpcMapper drops and counts such points.
constexpr double kGhprMaxDistanceM = 1e12;

const char* KernelName(GhprKernel kernel);
/// Parses "exponential" or "linear". @throws std::invalid_argument otherwise.
GhprKernel ParseKernel(const std::string& name);

/// Outcome of GHPR on one cloud. Expected data problems are statuses, not exceptions, so a closed
/// loop survives a bad frame.
enum class GhprStatus {
  kOk,
  kTooFewPoints,   ///< fewer than 4 points
  kDegenerate,     ///< all points and the viewpoint lie in one plane (or line): no volume
  kGammaTooSmall,  ///< linear kernel with gamma <= the largest distance to the viewpoint
};
const char* StatusName(GhprStatus status);

struct GhprResult {
  GhprStatus status = GhprStatus::kTooFewPoints;
  std::string message;           ///< human-readable reason when status != kOk
  FreeSpaceMesh mesh;            ///< faces not yet classified (face_traversable empty)
  bool viewpoint_on_hull = false;
  bool used_reference_hull = false;  ///< CGAL's quickhull computed this hull (asked for, or degenerate input)
  double transform_ms = 0.0;     ///< wall time of the image transform
  double hull_ms = 0.0;          ///< wall time of the convex hull
  double mesh_ms = 0.0;          ///< wall time of carrying the hull back to the points
};

/// Runs GHPR on `points` seen from `viewpoint`: maps every point p (relative to the viewpoint,
/// d = |p|) to p/d * f(d), adds the origin, takes the 3D convex hull with exact predicates (CGAL)
/// and keeps the hull vertices other than the origin as the visible set. The hull connectivity,
/// carried back to the original points, is the free-space mesh (see FreeSpaceMesh for orientation
/// and the treatment of the viewpoint).
///
/// @pre every point is finite and farther than a few micrometres from the viewpoint (the mapper
///      drops the others and counts them).
/// @throws std::invalid_argument for an invalid config or a point that breaks the precondition.
GhprResult ComputeGhpr(const Points& points, const Vec3& viewpoint, const Ghpr::Config& config);

}  // namespace ovpc
