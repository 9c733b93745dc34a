#include "ovpc/backends/map_selection.h"

namespace ovpc::backends {
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
    case MapSelection::Kind::kOctoMap: return std::make_unique<OctoMapBackend>(selection.octomap, faces);
    case MapSelection::Kind::kElevation: return std::make_unique<ElevationMapBackend>(selection.elevation, faces);
    case MapSelection::Kind::kOvpc: break;
  }
  return nullptr;
}

}  // namespace ovpc::backends
