// Ray casting against the world with Embree 3: the terrain grid as triangles (the same split as the
// physics heightfield) and every solid tessellated finely enough (chord error below
// max_chord_error_m; boxes and the terrain are exact). The ego vehicle is not in this scene, so the
// LiDAR can never hit it.
#pragma once

#include <cstddef>
#include <limits>
#include <memory>
#include <vector>

#include "ovpc/core/types.h"
#include "ovpc/sim/terrain.h"
#include "ovpc/sim/world.h"

namespace ovpc::sim {

class RayCaster {
 public:
  struct Config {
    double max_chord_error_m = 0.002;  ///< tessellation of cylinders and ellipsoids
    /// Threads Embree may use to build the BVH; ray queries run on the caller's thread.
    int build_threads = 1;

    /// @throws std::invalid_argument naming the offending field.
    void Validate() const;
  };

  /// What a ray hit: the distance along the unit direction, and the surface.
  struct Hit {
    static constexpr int kNone = -2;
    static constexpr int kTerrain = -1;
    double range_m = std::numeric_limits<double>::infinity();
    int surface = kNone;  ///< kNone, kTerrain, or the index into the solids
    bool hit() const { return surface != kNone; }
  };

  /// @throws std::invalid_argument on a bad config, std::runtime_error if Embree fails.
  RayCaster(const Heightfield& terrain, const std::vector<Solid>& solids, const Config& config);
  RayCaster(const Heightfield& terrain, const std::vector<Solid>& solids)
      : RayCaster(terrain, solids, Config{}) {}
  ~RayCaster();
  RayCaster(RayCaster&&) noexcept;
  RayCaster& operator=(RayCaster&&) noexcept;
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  /// The first surface along the ray within (0, max_range_m]; `direction` must be unit length.
  /// Thread-safe (Embree scenes are read-only after the build).
  Hit Cast(const Vec3& origin, const Vec3& direction, double max_range_m) const;

  /// Casts up to kFanSize rays from one origin as one Embree packet (a LiDAR firing): the same
  /// hits as Cast, faster for such a coherent fan. `directions` and `hits` hold `count` entries.
  static constexpr int kFanSize = 16;
  void CastFan(const Vec3& origin, const Vec3* directions, int count, double max_range_m,
               Hit* hits) const;

  std::size_t num_triangles() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The triangles the caster is built from, for tests and pictures.
struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<Triangle> triangles;
};
TriangleMesh TessellateSolid(const Solid& solid, double max_chord_error_m);
TriangleMesh TessellateTerrain(const Heightfield& terrain);

}  // namespace ovpc::sim
