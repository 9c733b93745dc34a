#include <stdexcept>

#include "ovpc/sim/renderer.h"

namespace ovpc::sim {

void Overlay::AddPoints(const Points& points_X, const Eigen::Isometry3d& T_W_X, const Rgba& rgba) {
  points.reserve(points.size() + points_X.size());
  for (const Vec3& p : points_X) points.push_back({T_W_X * p, rgba});
}

void Overlay::AddFreeSpaceMesh(const FreeSpaceMesh& mesh_L, const Eigen::Isometry3d& T_W_L,
                               const Rgba& traversable_rgba, const Rgba& blocked_rgba) {
  const int base = static_cast<int>(mesh_vertices_W.size());
  mesh_vertices_W.reserve(mesh_vertices_W.size() + mesh_L.vertices.size());
  for (const Vec3& v : mesh_L.vertices) mesh_vertices_W.push_back(T_W_L * v);
  for (std::size_t f = 0; f < mesh_L.triangles.size(); ++f) {
    if (mesh_L.TouchesViewpoint(f)) continue;
    const Triangle& t = mesh_L.triangles[f];
    mesh_triangles.push_back({base + t[0], base + t[1], base + t[2]});
    const bool traversable = f < mesh_L.face_traversable.size() && mesh_L.face_traversable[f] != 0;
    mesh_face_rgba.push_back(traversable ? traversable_rgba : blocked_rgba);
  }
}

void Overlay::Validate() const {
  if (mesh_face_rgba.size() != mesh_triangles.size()) {
    throw std::invalid_argument("Overlay: mesh_face_rgba needs one colour per mesh triangle");
  }
  const int n = static_cast<int>(mesh_vertices_W.size());
  for (const Triangle& t : mesh_triangles) {
    for (const int i : t) {
      if (i < 0 || i >= n) throw std::invalid_argument("Overlay: mesh triangle index out of range");
    }
  }
}

}  // namespace ovpc::sim
