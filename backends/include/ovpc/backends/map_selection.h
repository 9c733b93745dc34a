// The map backends by name, for the testbed's comparisons with OVPC (docs/BACKENDS.md): which one
// runs and the comparison backends' settings, and the factory that makes the one named.
#pragma once

#include <memory>

#include "ovpc/backends/elevation_backend.h"
#include "ovpc/backends/octomap_backend.h"
#include "ovpc/core/traversability.h"
#include "ovpc/navigation/map_backend.h"
#include "ovpc/core/config_fields.h"

namespace ovpc::backends {

/// The testbed's `navigator.map`, `navigator.octomap` and `navigator.elevation` (keys in
/// its VisitFields). The OVPC backend's settings are the navigator's own (Config::ovpc).
struct MapSelection {
  enum class Kind { kOvpc, kOctoMap, kElevation };
  Kind map = Kind::kOvpc;
  OctoMapBackend::Config octomap;
  ElevationMapBackend::Config elevation;
  template <class C, class V>
  static void VisitFields(C& c, V& v) {
    v.Choice(OVPC_FIELD(c, map), Choices<Kind>{{"ovpc", Kind::kOvpc}, {"octomap", Kind::kOctoMap}, {"elevation", Kind::kElevation}},
             "the testbed's map backend: ovpc (the navigator's own) or a comparison");
    v.Section(OVPC_FIELD(c, octomap), "the OctoMap backend: a fresh OcTree per update");
    v.Section(OVPC_FIELD(c, elevation), "the 2.5D elevation-map backend");
  }
  /// Both sections, whichever backend runs.
  /// @throws std::invalid_argument naming the offending field.
  void Validate() const;
};

/// "ovpc", "octomap" or "elevation".
const char* MapKindName(MapSelection::Kind kind);

/// The comparison backend `selection.map` names, judging slopes and steps with the OVPC face
/// test's thresholds `faces` (alpha_max_rad, delta_h_max_m: the navigator's
/// ovpc.mapper.traversability), so that every backend judges them alike. Null for kOvpc: the
/// navigator's default backend (Navigator::Plugins::map left null).
/// @throws std::invalid_argument for an invalid config.
std::unique_ptr<navigation::MapBackend> MakeMapBackend(const MapSelection& selection,
                                                       const Traversability::Config& faces);

}  // namespace ovpc::backends
