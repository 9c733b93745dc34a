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

namespace ovpc {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;

// Points closer than this to the viewpoint break the precondition of ComputeGhpr: the kernel is
// undefined at d = 0 and numerically meaningless next to it.
constexpr double kMinDistanceM = 1e-6;

using Clock = std::chrono::steady_clock;
double MsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Finds four image points (the origin among them) that span a volume, with exact predicates.
bool SpansVolume(const std::vector<Point3>& images) {
  const Point3& p0 = images.back();  // the viewpoint (origin)
  std::size_t i1 = 0;
  while (i1 < images.size() && images[i1] == p0) ++i1;
  if (i1 >= images.size()) return false;
  std::size_t i2 = 0;
  while (i2 < images.size() && CGAL::collinear(p0, images[i1], images[i2])) ++i2;
  if (i2 >= images.size()) return false;
  for (const Point3& p : images) {
    if (!CGAL::coplanar(p0, images[i1], images[i2], p)) return true;
  }
  return false;
}

}  // namespace

void GhprConfig::Validate() const {
  if (!std::isfinite(gamma)) throw std::invalid_argument("GhprConfig: gamma must be finite");
  if (kernel == GhprKernel::kExponential && !(gamma < 0.0)) {
    throw std::invalid_argument("GhprConfig: the exponential kernel needs gamma < 0 (paper: -0.03), got " +
                                std::to_string(gamma));
  }
  if (kernel == GhprKernel::kLinear && !(gamma > 0.0)) {
    throw std::invalid_argument(
        "GhprConfig: the linear kernel needs gamma > 0 and larger than the farthest point's distance, got " +
        std::to_string(gamma));
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

GhprResult ComputeGhpr(const Points& points, const Vec3& viewpoint, const GhprConfig& config) {
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
  // Image set: F(p) = p / d * f(d) with p relative to the viewpoint; the viewpoint (origin) last.
  std::vector<double> dist(n);
  double max_d = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!points[i].allFinite()) throw std::invalid_argument("ComputeGhpr: point " + std::to_string(i) + " is not finite");
    dist[i] = (points[i] - viewpoint).norm();
    if (!(dist[i] >= kMinDistanceM)) {
      throw std::invalid_argument("ComputeGhpr: point " + std::to_string(i) + " is at the viewpoint");
    }
    max_d = std::max(max_d, dist[i]);
  }
  if (config.kernel == GhprKernel::kLinear && !(config.gamma > max_d)) {
    std::ostringstream msg;
    msg << "linear kernel needs gamma > the farthest point's distance (" << max_d << " m), got "
        << config.gamma;
    result.status = GhprStatus::kGammaTooSmall;
    result.message = msg.str();
    return result;
  }
  std::vector<Point3> images(n + 1);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 rel = points[i] - viewpoint;
    const double scale = config.kernel == GhprKernel::kExponential
                             ? std::pow(dist[i], config.gamma - 1.0)
                             : (config.gamma - dist[i]) / dist[i];
    images[i] = Point3(rel.x() * scale, rel.y() * scale, rel.z() * scale);
  }
  images[n] = Point3(0.0, 0.0, 0.0);

  result.transform_ms = MsSince(t);
  if (!SpansVolume(images)) {
    result.status = GhprStatus::kDegenerate;
    result.message = "all points lie in one plane with the viewpoint: the hull has no volume";
    return result;
  }

  t = Clock::now();
  // Convex hull over indices, so that hull vertices come back as indices into the image set.
  using PointMap = CGAL::Pointer_property_map<Point3>::const_type;
  using Traits = CGAL::Extreme_points_traits_adapter_3<PointMap, CGAL::Convex_hull_traits_3<Kernel>>;
  std::vector<std::size_t> order(n + 1);
  for (std::size_t i = 0; i <= n; ++i) order[i] = i;
  std::vector<std::size_t> hull_vertices;            // image indices
  std::vector<std::array<std::size_t, 3>> hull_faces;  // indices into hull_vertices
  const Traits traits(CGAL::make_property_map(static_cast<const std::vector<Point3>&>(images)));
  CGAL::convex_hull_3<std::vector<std::size_t>::const_iterator, void, std::vector<std::size_t>,
                      std::vector<std::array<std::size_t, 3>>, Traits>(
      order.cbegin(), order.cend(), hull_vertices, hull_faces, traits);
  result.hull_ms = MsSince(t);
  t = Clock::now();

  // Mesh vertices: the visible points in ascending input order, then the viewpoint if on the hull.
  std::vector<std::size_t> sorted = hull_vertices;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> mesh_index_of_image(n + 1, -1);
  FreeSpaceMesh& mesh = result.mesh;
  for (std::size_t image : sorted) {
    if (image == n) continue;
    mesh_index_of_image[image] = static_cast<int>(mesh.vertices.size());
    mesh.vertices.push_back(points[image]);
    mesh.source_index.push_back(static_cast<int>(image));
  }
  result.viewpoint_on_hull = std::binary_search(sorted.begin(), sorted.end(), n);
  if (result.viewpoint_on_hull) {
    mesh.viewpoint_vertex = static_cast<int>(mesh.vertices.size());
    mesh_index_of_image[n] = mesh.viewpoint_vertex;
    mesh.vertices.push_back(viewpoint);
    mesh.source_index.push_back(-1);
  }
  // The hull's faces are oriented outwards in image space. The map is radial, so the original
  // triangles keep their orientation as seen from the viewpoint; reversing them makes the normals
  // point into the enclosed free space.
  mesh.triangles.reserve(hull_faces.size());
  for (const auto& f : hull_faces) {
    mesh.triangles.push_back({mesh_index_of_image[hull_vertices[f[0]]],
                              mesh_index_of_image[hull_vertices[f[2]]],
                              mesh_index_of_image[hull_vertices[f[1]]]});
  }
  result.mesh_ms = MsSince(t);
  result.status = GhprStatus::kOk;
  return result;
}

}  // namespace ovpc
