#include "ovpc/core/traversability.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace ovpc {

void Traversability::Config::Validate() const {
  if (!(alpha_max_rad > 0.0 && alpha_max_rad <= kPi / 2)) {
    throw std::invalid_argument("Traversability::Config: alpha_max must be in (0, 90] deg, got " +
                                std::to_string(RadToDeg(alpha_max_rad)) + " deg");
  }
  if (!(delta_h_max_m > 0.0) || !std::isfinite(delta_h_max_m)) {
    throw std::invalid_argument("Traversability::Config: delta_h_max must be > 0 m, got " +
                                std::to_string(delta_h_max_m));
  }
  if (!(noise_floor_m >= 0.0) || !(noise_floor_m < delta_h_max_m)) {
    throw std::invalid_argument("Traversability::Config: noise_floor must be in [0, delta_h_max), got " +
                                std::to_string(noise_floor_m));
  }
}

void ClassifyFaces(const Traversability::Config& config, FreeSpaceMesh* mesh, const Vec3& up) {
  if (!up.allFinite() || std::abs(up.norm() - 1.0) > 1e-6) {
    throw std::invalid_argument("ClassifyFaces: up must be a unit vector");
  }
  const std::size_t num_faces = mesh->triangles.size();
  mesh->face_normals.resize(num_faces);
  mesh->face_traversable.resize(num_faces);
  const double cos_alpha_max = std::cos(config.alpha_max_rad);
  // With a noise floor: the local surface at each vertex, the area-weighted sum of the normals of
  // the faces around it (faces touching the viewpoint left out).
  std::vector<Vec3> vertex_area_normal;
  if (config.noise_floor_m > 0.0 && config.noise_floor_on_slopes) {
    vertex_area_normal.assign(mesh->vertices.size(), Vec3::Zero());
    for (std::size_t f = 0; f < num_faces; ++f) {
      if (mesh->TouchesViewpoint(f)) continue;
      const Triangle& t = mesh->triangles[f];
      const Vec3 cross = (mesh->vertices[t[1]] - mesh->vertices[t[0]]).cross(mesh->vertices[t[2]] - mesh->vertices[t[0]]);
      for (int k = 0; k < 3; ++k) vertex_area_normal[t[k]] += cross;
    }
  }
  for (std::size_t f = 0; f < num_faces; ++f) {
    const Triangle& t = mesh->triangles[f];
    const Vec3& a = mesh->vertices[t[0]];
    const Vec3& b = mesh->vertices[t[1]];
    const Vec3& c = mesh->vertices[t[2]];
    const Vec3 cross = (b - a).cross(c - a);
    const double norm = cross.norm();
    if (!(norm > 0.0)) {
      mesh->face_normals[f] = Vec3::Zero();
      mesh->face_traversable[f] = 0;
      continue;
    }
    const Vec3 normal = cross / norm;
    mesh->face_normals[f] = normal;
    const double ha = a.dot(up), hb = b.dot(up), hc = c.dot(up);
    const double spread = std::max({ha, hb, hc}) - std::min({ha, hb, hc});
    // angle < alpha_max  <=>  cos(angle) > cos(alpha_max); ceilings have cos(angle) < 0.
    const double cos_angle = normal.dot(up);
    // Below the noise floor only faces looking down more than 60 deg (ceilings, the underside of a
    // roof) keep the angle test: folds of noisy ground stand on edge or lean over a little.
    bool flat_enough = cos_angle > cos_alpha_max || (spread < config.noise_floor_m && cos_angle > -0.5);
    bool low_step = spread < config.delta_h_max_m;
    if ((!flat_enough || !low_step) && cos_angle > 0.0 && !vertex_area_normal.empty()) {
      // A face on a slope: its height spread includes the slope's rise (a sliver tilted by noise, or
      // a long face where the slope was seen sparsely, at a grazing angle), but its relief across the
      // local surface around it is what a step or the noise makes. If that surface passes the angle
      // test and the face lies within the noise floor of it, the face's tilt is noise and its height
      // spread is the slope's, not a step's. At a curb or a drop the surface around bends with the
      // step, so the face stands out of it by most of the step's height.
      const Vec3 local = vertex_area_normal[t[0]] + vertex_area_normal[t[1]] + vertex_area_normal[t[2]];
      const double local_norm = local.norm();
      if (local_norm > 0.0 && local.dot(up) > cos_alpha_max * local_norm) {
        const Vec3 n = local / local_norm;
        const double da = a.dot(n), db = b.dot(n), dc = c.dot(n);
        if (std::max({da, db, dc}) - std::min({da, db, dc}) < config.noise_floor_m) flat_enough = low_step = true;
      }
    }
    mesh->face_traversable[f] = (flat_enough && low_step && !mesh->TouchesViewpoint(f)) ? 1 : 0;
  }
}

}  // namespace ovpc
