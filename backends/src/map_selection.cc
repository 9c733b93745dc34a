#include "ovpc/backends/map_selection.h"

namespace ovpc::backends {
namespace {

ColumnMap::Config WithFaceThresholds(ColumnMap::Config map, const Traversability::Config& faces) {
  map.alpha_max_rad = faces.alpha_max_rad;
  map.delta_h_max_m = faces.delta_h_max_m;
  return map;
}

}  // namespace

void MapSelection::Validate() const {
  octomap.Validate();
  elevation.Validate();
}

const char* MapKindName(MapSelection::Kind kind) {
  switch (kind) {
    case MapSelection::Kind::kOvpc: return "ovpc";
    case MapSelection::Kind::kOctoMap: return "octomap";
    case MapSelection::Kind::kElevation: return "elevation";
  }
  return "unknown";
}

std::unique_ptr<navigation::MapBackend> MakeMapBackend(const MapSelection& selection,
                                                       const Traversability::Config& faces) {
  switch (selection.map) {
    case MapSelection::Kind::kOctoMap: {
      OctoMapBackend::Config c = selection.octomap;
      c.map = WithFaceThresholds(c.map, faces);
      return std::make_unique<OctoMapBackend>(c);
    }
    case MapSelection::Kind::kElevation: {
      ElevationMapBackend::Config c = selection.elevation;
      c.map = WithFaceThresholds(c.map, faces);
      return std::make_unique<ElevationMapBackend>(c);
    }
    case MapSelection::Kind::kOvpc: break;
  }
  return nullptr;
}

}  // namespace ovpc::backends
