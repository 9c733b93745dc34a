// The comparison backends' settings, listed once per Config in the manner of
// navigation/config_fields.h (same visitor: Field, Choice, Section). The testbed reads and writes them
// under `navigator:` beside the navigator's own keys. Left out: ColumnMap::Config's per-update inputs
// and its traversability thresholds (MakeMapBackend takes them from the OVPC backend's).
#pragma once

#include "ovpc/backends/map_selection.h"

namespace ovpc::backends {

template <class V>
void VisitFields(V& v, ColumnMap::Config& c) {
  v.Field("max_projection_distance_m", c.max_projection_distance_m);
  v.Field("normal_radius_m", c.normal_radius_m);
}

template <class V>
void VisitFields(V& v, OctoMapBackend::Config& c) {
  v.Field("resolution_m", c.resolution_m);
  v.Section("map", c.map);
}

template <class V>
void VisitFields(V& v, baselines::ElevationMap::Config& c) {
  v.Field("resolution_m", c.resolution_m);
  v.Field("length_m", c.length_m);
  v.Field("mahalanobis_threshold", c.mahalanobis_threshold);
  v.Field("sensor_sigma_m", c.sensor_sigma_m);
  v.Field("sensor_sigma_per_m", c.sensor_sigma_per_m);
  v.Field("min_height_above_base_m", c.min_height_above_base_m);
  v.Field("max_height_above_base_m", c.max_height_above_base_m);
}

template <class V>
void VisitFields(V& v, ElevationMapBackend::Config& c) {
  v.Section("grid", c.grid);
  v.Section("map", c.map);
}

/// The keys sit in the `navigator:` section, after the navigator's own.
template <class V>
void VisitFields(V& v, MapSelection& c) {
  v.Choice("map", c.map, {{"ovpc", MapSelection::Kind::kOvpc},
                          {"octomap", MapSelection::Kind::kOctoMap},
                          {"elevation", MapSelection::Kind::kElevation}});
  v.Section("octomap", c.octomap);
  v.Section("elevation", c.elevation);
}

}  // namespace ovpc::backends
