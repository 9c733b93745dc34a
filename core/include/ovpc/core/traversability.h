// Per-face traversability on the free-space mesh (paper, "Map Representation for Path Planning").
#pragma once

#include "ovpc/core/free_space_mesh.h"

namespace ovpc {

struct TraversabilityConfig {
  double alpha_max_rad = DegToRad(30.0);  ///< max surface angle between normal and up
  double delta_h_max_m = 0.25;                 ///< max height spread among a face's vertices
  Vec3 up = Vec3::UnitZ();                     ///< gravity-up in the mesh frame (unit)
  /// @throws std::invalid_argument naming the offending field.
  void Validate() const;
};

/// Computes unit face normals (into free space) and the traversable flag of every face:
/// angle(normal, up) < alpha_max and height spread < delta_h_max, and the face does not touch the
/// viewpoint. Ceilings (normals pointing down) fail the angle test. Degenerate (zero-area) faces get
/// a zero normal and are not traversable.
void ClassifyFaces(const TraversabilityConfig& config, FreeSpaceMesh* mesh);

}  // namespace ovpc
