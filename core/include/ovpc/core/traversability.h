// Per-face traversability on the free-space mesh (paper, "Map Representation for Path Planning").
#pragma once

#include "ovpc/core/free_space_mesh.h"
#include "ovpc/core/config_fields.h"

namespace ovpc {

/// The face traversability test (ClassifyFaces).
struct Traversability {
  struct Config {
    double alpha_max_rad = DegToRad(30.0);  ///< max surface angle between normal and up
    double delta_h_max_m = 0.25;                 ///< max height spread among a face's vertices
    /// Faces whose vertices span less height than this are judged by the height test alone, unless
    /// they look down by more than 60 deg (a ceiling): on noisy ground, slivers a few centimetres
    /// across get normals that say nothing about the slope (range noise of 1.5 cm over 5 cm tilts a
    /// face by 17 deg), and where the ground crosses a voxel boundary two voxel centroids a few
    /// centimetres apart stand one above the other and make folds whose faces stand on edge or lean
    /// over. On a slope the same holds across the local surface: a face that fails the angle test is
    /// traversable when the surface around it (the area-weighted mean normal of the faces at its
    /// vertices) passes the angle test and the face's vertices lie within this distance along that
    /// surface's normal (`noise_floor_on_slopes`). 0 is the paper's rule.
    double noise_floor_m = 0.0;
    /// Also apply the noise floor across the local surface on slopes (see above). Off: the paper's
    /// rule above the noise floor.
    bool noise_floor_on_slopes = false;
    template <class C, class V>
    static void VisitFields(C& c, V& v) {
      v.Field(OVPC_FIELD(c, alpha_max_rad), "rad", "paper: 30 deg");
      v.Field(OVPC_FIELD(c, delta_h_max_m), "m", "paper");
      v.Field(OVPC_FIELD(c, noise_floor_m), "m", "flatter faces skip the angle test; 0: paper");
      v.Field(OVPC_FIELD(c, noise_floor_on_slopes), "", "the noise floor across the local surface too; off: paper");
    }
    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };
};

/// Computes unit face normals (into free space) and the traversable flag of every face:
/// angle(normal, up) < alpha_max and height spread < delta_h_max, and the face does not touch the
/// viewpoint. Ceilings (normals pointing down) fail the angle test. Faces lower than
/// `noise_floor_m` that do not look down skip the angle test, and so do faces thinner than it across a
/// local surface that passes the angle test (see Traversability::Config::noise_floor_m). Degenerate (zero-area) faces get
/// a zero normal and are not traversable. `up` is gravity-up in the mesh frame.
/// @throws std::invalid_argument if `up` is not a unit vector.
void ClassifyFaces(const Traversability::Config& config, FreeSpaceMesh* mesh, const Vec3& up = Vec3::UnitZ());

}  // namespace ovpc
