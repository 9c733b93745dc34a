#include "ovpc/core/ghpr.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>

#include <CGAL/Convex_hull_traits_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Extreme_points_traits_adapter_3.h>
#include <CGAL/convex_hull_3.h>
#include <CGAL/property_map.h>

#include "incremental_hull.h"
#include "internal_util.h"

namespace ovpc {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;

// Points closer than this to the viewpoint break the precondition of ComputeGhpr: the kernel is
// undefined at d = 0 and numerically meaningless next to it.
constexpr double kMinDistanceM = 1e-6;

using internal::Clock;
using internal::MsSince;

Point3 ToCgal(const Vec3& p) { return Point3(p.x(), p.y(), p.z()); }

// Whether `points` and `origin` span a volume, with exact predicates on the coordinates as given.
// Usually the first few points decide.
bool SpansVolume(const Points& points, const Vec3& origin) {
  const Point3 v = ToCgal(origin);
  std::size_t i1 = 0;
  while (i1 < points.size() && ToCgal(points[i1]) == v) ++i1;
  if (i1 >= points.size()) return false;
  const Point3 p1 = ToCgal(points[i1]);
  std::size_t i2 = 0;
  while (i2 < points.size() && CGAL::collinear(v, p1, ToCgal(points[i2]))) ++i2;
  if (i2 >= points.size()) return false;
  const Point3 p2 = ToCgal(points[i2]);
  for (const Vec3& p : points) {
    if (!CGAL::coplanar(v, p1, p2, ToCgal(p))) return true;
  }
  return false;
}

// The reference path: CGAL's quickhull over point indices (exact predicates), outputs as in
// internal::IncrementalHull (ascending vertex indices, outward faces as point indices).
void CgalHull(const Points& images, std::vector<int>* vertices, std::vector<std::array<int, 3>>* faces) {
  std::vector<Point3> pts;
  pts.reserve(images.size());
  for (const Vec3& p : images) pts.push_back(ToCgal(p));
  using PointMap = CGAL::Pointer_property_map<Point3>::const_type;
  using Traits = CGAL::Extreme_points_traits_adapter_3<PointMap, CGAL::Convex_hull_traits_3<Kernel>>;
  std::vector<std::size_t> order(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) order[i] = i;
  std::vector<std::size_t> hull_vertices;              // point indices
  std::vector<std::array<std::size_t, 3>> hull_faces;  // indices into hull_vertices
  const Traits traits(CGAL::make_property_map(static_cast<const std::vector<Point3>&>(pts)));
  CGAL::convex_hull_3<std::vector<std::size_t>::const_iterator, void, std::vector<std::size_t>,
                      std::vector<std::array<std::size_t, 3>>, Traits>(order.cbegin(), order.cend(), hull_vertices,
                                                                       hull_faces, traits);
  faces->clear();
  for (const auto& f : hull_faces) {
    faces->push_back({static_cast<int>(hull_vertices[f[0]]), static_cast<int>(hull_vertices[f[1]]),
                      static_cast<int>(hull_vertices[f[2]])});
  }
  vertices->assign(hull_vertices.begin(), hull_vertices.end());
  std::sort(vertices->begin(), vertices->end());
}

// Per-thread buffers reused across calls.
struct Scratch {
  Points images;
  internal::HullWorkspace hull;
  std::vector<int> hull_vertices;
  std::vector<std::array<int, 3>> hull_faces;
  std::vector<int> mesh_index;
  std::vector<int> dedup_order, dedup_original;
  std::vector<char> dedup_repeat;
  Points dedup_images;
};

// Exact duplicate image points (repeated input points, e.g. a scanner's self-hits) make the
// incremental hull stop as degenerate, though the hull of the distinct points is the same. Drops
// the repeats (keeping the first of each), runs the fast hull on the rest and maps its vertices and
// faces back to image indices. False when there are no duplicates or the rest is degenerate too.
bool FastHullWithoutDuplicates(const Points& images, Scratch* s, std::vector<int>* vertices,
                               std::vector<std::array<int, 3>>* faces) {
  std::vector<int>& order = s->dedup_order;
  order.resize(images.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  const auto less = [&](int a, int b) {
    const Vec3 &p = images[a], &q = images[b];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<char>& repeat = s->dedup_repeat;
  repeat.assign(images.size(), 0);
  bool any = false;
  for (std::size_t k = 1; k < order.size(); ++k) {
    if (images[order[k]] == images[order[k - 1]]) repeat[order[k]] = 1, any = true;  // order[k - 1] is smaller
  }
  if (!any) return false;
  Points& distinct = s->dedup_images;
  std::vector<int>& original = s->dedup_original;
  distinct.clear();
  original.clear();
  for (std::size_t i = 0; i < images.size(); ++i) {
    if (repeat[i]) continue;
    distinct.push_back(images[i]);
    original.push_back(static_cast<int>(i));
  }
  if (internal::IncrementalHull(distinct, &s->hull, vertices, faces) != internal::HullStatus::kOk) return false;
  for (int& v : *vertices) v = original[v];  // increasing map: stays ascending
  for (auto& f : *faces) {
    for (int& v : f) v = original[v];
  }
  return true;
}

// Image set: F(p) = p / d * f(d) with p relative to the viewpoint; the viewpoint (origin) last.
// Returns the farthest point's distance. @throws std::invalid_argument for a point that is not
// finite, farther than 1e12 m or at the viewpoint.
double TransformToImages(const Points& points, const Vec3& viewpoint, const Ghpr::Config& config, Points* images) {
  const std::size_t n = points.size();
  images->resize(n + 1);
  double max_d = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!points[i].allFinite()) throw std::invalid_argument("ComputeGhpr: point " + std::to_string(i) + " is not finite");
    const Vec3 rel = points[i] - viewpoint;
    if (!(rel.cwiseAbs().maxCoeff() <= kGhprMaxDistanceM)) {
      throw std::invalid_argument("ComputeGhpr: point " + std::to_string(i) + " is farther than 1e12 m from the viewpoint");
    }
    const double d = rel.norm();
    if (!(d >= kMinDistanceM)) {
      throw std::invalid_argument("ComputeGhpr: point " + std::to_string(i) + " is at the viewpoint");
    }
    max_d = std::max(max_d, d);
    const double scale = config.kernel == GhprKernel::kExponential ? std::pow(d, config.gamma - 1.0)
                                                                   : (config.gamma - d) / d;
    (*images)[i] = rel * scale;
  }
  (*images)[n] = Vec3::Zero();
  return max_d;
}

// The mesh from the hull of the images (scratch->hull_vertices, ascending, and hull_faces, outward).
void BuildMesh(const Points& points, const Vec3& viewpoint, Scratch* scratch, GhprResult* result) {
  const std::size_t n = points.size();
  const std::vector<int>& hull_vertices = scratch->hull_vertices;
  // Mesh vertices: the visible points in ascending input order, then the viewpoint if on the hull.
  std::vector<int>& mesh_index_of_image = scratch->mesh_index;
  mesh_index_of_image.assign(n + 1, -1);
  FreeSpaceMesh& mesh = result->mesh;
  mesh.viewpoint = viewpoint;
  mesh.vertices.reserve(hull_vertices.size());
  mesh.source_index.reserve(hull_vertices.size());
  for (int image : hull_vertices) {
    if (image == static_cast<int>(n)) continue;
    mesh_index_of_image[image] = static_cast<int>(mesh.vertices.size());
    mesh.vertices.push_back(points[image]);
    mesh.source_index.push_back(image);
  }
  result->viewpoint_on_hull = !hull_vertices.empty() && hull_vertices.back() == static_cast<int>(n);
  if (result->viewpoint_on_hull) {
    mesh.viewpoint_vertex = static_cast<int>(mesh.vertices.size());
    mesh_index_of_image[n] = mesh.viewpoint_vertex;
    mesh.vertices.push_back(viewpoint);
    mesh.source_index.push_back(-1);
  }
  // The hull's faces are oriented outwards in image space. The map is radial, so the original
  // triangles keep their orientation as seen from the viewpoint; reversing them makes the normals
  // point into the enclosed free space.
  mesh.triangles.reserve(scratch->hull_faces.size());
  for (const auto& f : scratch->hull_faces) {
    mesh.triangles.push_back({mesh_index_of_image[f[0]], mesh_index_of_image[f[2]], mesh_index_of_image[f[1]]});
  }
}

}  // namespace

void Ghpr::Config::Validate() const {
  // %g: a rejected 1e300 is one short line, not 301 digits.
  const auto shown = [](double v) {
    std::ostringstream out;
    out << v;
    return out.str();
  };
  if (!std::isfinite(gamma)) throw std::invalid_argument("Ghpr::Config: gamma must be finite");
  // Bounds that keep the image transform well conditioned: past them the image points collapse or
  // overflow and the hull takes minutes (gamma = -300: 74 s) for a meaningless map.
  if (kernel == GhprKernel::kExponential && !(gamma < 0.0 && gamma >= -1.0)) {
    throw std::invalid_argument("Ghpr::Config: the exponential kernel needs gamma in [-1, 0) (paper: -0.03), got " +
                                shown(gamma));
  }
  if (kernel == GhprKernel::kLinear && gamma > 1e7) {
    throw std::invalid_argument("Ghpr::Config: the linear kernel needs gamma at most 1e7 m, got " + shown(gamma));
  }
  if (kernel == GhprKernel::kLinear && !(gamma > 0.0)) {
    throw std::invalid_argument(
        "Ghpr::Config: the linear kernel needs gamma > 0 and larger than the farthest point's distance, got " +
        shown(gamma));
  }
}

const char* KernelName(GhprKernel kernel) {
  return kernel == GhprKernel::kExponential ? "exponential" : "linear";
}

GhprKernel ParseKernel(const std::string& name) {
  if (name == "exponential" || name == "exp") return GhprKernel::kExponential;
  if (name == "linear" || name == "lin") return GhprKernel::kLinear;
  throw std::invalid_argument("unknown GHPR kernel '" + name + "' (expected exponential or linear)");
}

const char* StatusName(GhprStatus status) {
  switch (status) {
    case GhprStatus::kOk: return "ok";
    case GhprStatus::kTooFewPoints: return "too_few_points";
    case GhprStatus::kDegenerate: return "degenerate";
    case GhprStatus::kGammaTooSmall: return "gamma_too_small";
  }
  return "unknown";
}

GhprResult ComputeGhpr(const Points& points, const Vec3& viewpoint, const Ghpr::Config& config) {
  config.Validate();
  if (!viewpoint.allFinite()) throw std::invalid_argument("ComputeGhpr: viewpoint is not finite");
  GhprResult result;
  const std::size_t n = points.size();
  if (n < 4) {
    result.status = GhprStatus::kTooFewPoints;
    result.message = "need at least 4 usable points, got " + std::to_string(n);
    return result;
  }

  auto t = Clock::now();
  // Buffers live per thread and are reused, so a steady stream of clouds allocates nothing new.
  thread_local Scratch scratch;
  Points& images = scratch.images;
  const double max_d = TransformToImages(points, viewpoint, config, &images);
  if (config.kernel == GhprKernel::kLinear && !(config.gamma > max_d)) {
    std::ostringstream msg;
    msg << "linear kernel needs gamma > the farthest point's distance (" << max_d << " m), got "
        << config.gamma;
    result.status = GhprStatus::kGammaTooSmall;
    result.message = msg.str();
    return result;
  }
  result.transform_ms = MsSince(t);

  // Tested on the input: the image transform rounds, so points exactly in one plane with the
  // viewpoint (a line y = 5, z = -1 seen from the origin) can give image points a few ulps off the
  // plane, which the hull then takes for a sliver of a volume.
  if (!SpansVolume(points, viewpoint)) {
    result.status = GhprStatus::kDegenerate;
    result.message = "all points lie in one plane with the viewpoint: the hull has no volume";
    return result;
  }

  t = Clock::now();
  std::vector<int>& hull_vertices = scratch.hull_vertices;         // image indices, ascending
  std::vector<std::array<int, 3>>& hull_faces = scratch.hull_faces;  // image indices, outward
  const bool fast = !config.reference_hull &&
                    (internal::IncrementalHull(images, &scratch.hull, &hull_vertices, &hull_faces) ==
                         internal::HullStatus::kOk ||
                     FastHullWithoutDuplicates(images, &scratch, &hull_vertices, &hull_faces));
  if (!fast) {
    // Degenerate input (coplanar or duplicate image points) or asked for: CGAL's quickhull decides.
    if (!SpansVolume(images, images.back())) {  // the viewpoint (origin) is the last image
      result.status = GhprStatus::kDegenerate;
      result.message = "all points lie in one plane with the viewpoint: the hull has no volume";
      return result;
    }
    CgalHull(images, &hull_vertices, &hull_faces);
    result.used_reference_hull = true;
  }
  result.hull_ms = MsSince(t);
  t = Clock::now();

  BuildMesh(points, viewpoint, &scratch, &result);
  result.mesh_ms = MsSince(t);
  result.status = GhprStatus::kOk;
  return result;
}

}  // namespace ovpc
