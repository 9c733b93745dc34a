#include <stdexcept>

#include "ovpc/sim/renderer.h"

namespace ovpc::sim {

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
