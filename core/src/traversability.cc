#include "ovpc/core/traversability.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ovpc {

void TraversabilityConfig::Validate() const {
  if (!(alpha_max_rad > 0.0 && alpha_max_rad <= kPi / 2)) {
    throw std::invalid_argument("TraversabilityConfig: alpha_max must be in (0, 90] deg, got " +
                                std::to_string(RadToDeg(alpha_max_rad)) + " deg");
  }
  if (!(delta_h_max_m > 0.0) || !std::isfinite(delta_h_max_m)) {
    throw std::invalid_argument("TraversabilityConfig: delta_h_max must be > 0 m, got " +
                                std::to_string(delta_h_max_m));
  }
  if (!(noise_floor_m >= 0.0) || !(noise_floor_m < delta_h_max_m)) {
    throw std::invalid_argument("TraversabilityConfig: noise_floor must be in [0, delta_h_max), got " +
                                std::to_string(noise_floor_m));
  }
  if (!up.allFinite() || std::abs(up.norm() - 1.0) > 1e-6) {
    throw std::invalid_argument("TraversabilityConfig: up must be a unit vector");
  }
}

void ClassifyFaces(const TraversabilityConfig& config, FreeSpaceMesh* mesh) {
  const std::size_t num_faces = mesh->triangles.size();
  mesh->face_normals.resize(num_faces);
  mesh->face_traversable.resize(num_faces);
  const double cos_alpha_max = std::cos(config.alpha_max_rad);
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
    const double ha = a.dot(config.up), hb = b.dot(config.up), hc = c.dot(config.up);
    const double spread = std::max({ha, hb, hc}) - std::min({ha, hb, hc});
    // angle < alpha_max  <=>  cos(angle) > cos(alpha_max); ceilings have cos(angle) < 0.
    const double cos_angle = normal.dot(config.up);
    // Below the noise floor only faces looking down more than 60 deg (ceilings, the underside of a
    // roof) keep the angle test: folds of noisy ground stand on edge or lean over a little.
    const bool flat_enough = cos_angle > cos_alpha_max || (spread < config.noise_floor_m && cos_angle > -0.5);
    const bool low_step = spread < config.delta_h_max_m;
    mesh->face_traversable[f] = (flat_enough && low_step && !mesh->TouchesViewpoint(f)) ? 1 : 0;
  }
}

}  // namespace ovpc
